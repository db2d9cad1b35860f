#pragma once
#include <CLI/CLI.hpp>

#include "game/render/offscreen_render.hpp"

namespace ikebana::game {

// `ikebana render` (game/render/offscreen_render.hpp does the work).
void add_render_command(CLI::App& app, int& exit_code);

} // namespace ikebana::game
