#pragma once
#include <CLI/CLI.hpp>

namespace ikebana::game {

// `ikebana experiment`: the paper's repeated-insertion experiment, headless.
void add_experiment_command(CLI::App& app, int& exit_code);

} // namespace ikebana::game
