#pragma once
// A recorded session played back in the window, for a teacher reviewing a trainee (or a trainee
// themselves): play and pause (Space), speed, a timeline to scrub to any moment with the cuts, tilts
// and insertions marked on it (each a button that jumps there), and the camera free (arrows or a
// right-drag), whatever way the trainee looked. It plays on the deterministic clock, as `ikebana
// replay --json` does, so what is shown is what the headless replay checks; a jump, back or
// forth, starts from the moment kept before it (game/session/seekable_playback.hpp).
#include <cstdint>
#include <string>

namespace ikebana::game {

class WindowStack;

struct ReplayWindowOptions {
    std::string folder;
    double speed = 1.0;
    std::uint32_t width = 1280, height = 720;
    std::string stereo = "mono"; // its own window's display (render::parse_stereo_mode): a flat screen by default
    std::uint32_t frames = 0;   // stop after this many presented frames (0: until Esc or the window closes)
    std::string screenshot;     // the last frame, as PNG
    std::string state_out;      // what the window shows, as JSON each frame (game/session/window_state.hpp)
    bool validation = false;
};

// Its own window; with no display it says so (the headless replay is `--json`). The exit code.
int run_replay_window(const ReplayWindowOptions& options);
// In a window already open (the start screen's): until Esc, the Back button or the window's close.
// `presented` counts the frames drawn. The exit code (0, or 2 for a recording that cannot be read).
int play_recording(WindowStack& stack, const ReplayWindowOptions& options, std::uint32_t& presented);

} // namespace ikebana::game
