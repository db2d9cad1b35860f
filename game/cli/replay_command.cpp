#include "game/cli/replay_command.hpp"

#include <memory>

#include "game/app/replay_window.hpp"
#include "game/cli/lesson_command.hpp"

namespace ikebana::game {

void add_replay_command(CLI::App& app, int& exit_code) {
    auto args = std::make_shared<ReplayWindowOptions>();
    auto json = std::make_shared<std::string>();
    auto* replay = app.add_subcommand("replay", "Play a recorded session back: in the window (pause, speed, scrub, free camera, a timeline of cuts, "
                                                "tilts and insertions) or headless with --json, to the recorded score and state hash");
    replay->add_option("folder", args->folder, "The session's recording (`ikebana history` lists where each is)")->required();
    replay->add_option("--json", *json, "Headless: check the score and final state hash, and write the result as JSON here (- : only the JSON)");
    replay->add_option("--speed", args->speed, "The window's playback speed at the start (0.25 to 8)")->capture_default_str()->check(CLI::Range(0.25, 8.0));
    replay->add_option("--width", args->width, "The window's width")->capture_default_str()->check(CLI::Range(64u, 8192u));
    replay->add_option("--height", args->height, "The window's height")->capture_default_str()->check(CLI::Range(64u, 8192u));
    replay->add_option("--stereo", args->stereo, "The window's display: mono (a flat screen), sbs, rows (polarized displays) or anaglyph")->capture_default_str();
    replay->add_option("--frames", args->frames, "Stop after this many frames (tests)")->capture_default_str();
    replay->add_option("--screenshot", args->screenshot, "Write the last frame to this PNG");
    replay->add_option("--state-out", args->state_out, "Write what the window shows as JSON each frame (for scripts that work the window)");
    replay->callback([args, json, &exit_code] {
        exit_code = json->empty() ? run_replay_window(*args) : replay_session("ikebana replay: ", args->folder, *json);
    });
}

} // namespace ikebana::game
