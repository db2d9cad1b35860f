#pragma once
#include <CLI/CLI.hpp>

namespace ikebana::game {

// `ikebana predict TRIALS.csv [--species ID|FILE] -o OUT.csv`
void add_predict_command(CLI::App& app, int& exit_code);
int run_predict(const std::string& input, const std::string& species, const std::string& output);

} // namespace ikebana::game
