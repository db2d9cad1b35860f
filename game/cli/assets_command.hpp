#pragma once
#include <CLI/CLI.hpp>

namespace ikebana::game {

// `ikebana assets meshes [--out DIR]`: (re)generates the procedural glTF meshes.
void add_assets_command(CLI::App& app, int& exit_code);

} // namespace ikebana::game
