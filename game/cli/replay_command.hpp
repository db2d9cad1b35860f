#pragma once
// `ikebana replay DIR`: a recorded session (each stored window session has one, `ikebana history`
// says where; `lesson demo --record` writes one) played back. In the window: play, pause, speed,
// scrubbing to any moment, the camera free, and a timeline of the cuts, tilts and insertions. With
// `--json OUT` (or no display): headless on the deterministic clock, to the recorded score and final
// state hash or an error.
#include <CLI/CLI.hpp>

namespace ikebana::game {

void add_replay_command(CLI::App& app, int& exit_code);

} // namespace ikebana::game
