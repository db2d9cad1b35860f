#pragma once
#include <CLI/CLI.hpp>

namespace ikebana::game {

// `ikebana species check FILE...`: validates species files, prints every problem, exits non-zero on any.
void add_species_command(CLI::App& app, int& exit_code);
int check_species_files(const std::vector<std::string>& files);

} // namespace ikebana::game
