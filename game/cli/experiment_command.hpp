#pragma once
#include <CLI/CLI.hpp>

namespace ikebana::game {

// `ikebana experiment`: the paper's repeated-insertion experiment, headless.
void add_experiment_command(CLI::App& app, int& exit_code);
// `ikebana bench forces`: the paper's force scheme against full rate.
void add_force_bench_command(CLI::App& app, int& exit_code);

} // namespace ikebana::game
