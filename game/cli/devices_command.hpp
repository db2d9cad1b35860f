#pragma once
#include <CLI/CLI.hpp>

namespace ikebana::game {

// `ikebana devices`: what hidapi sees, and which profile each device matches.
void add_devices_command(CLI::App& app, int& exit_code);

} // namespace ikebana::game
