#pragma once
#include <CLI/CLI.hpp>

namespace ikebana::game {

// `ikebana validate MEASURED.csv [--species ID|FILE] --json OUT.json [--report DIR]
//  [--write-species EXT.json] [--seed S]`, and `ikebana validate --paper`.
void add_validate_command(CLI::App& app, int& exit_code);

} // namespace ikebana::game
