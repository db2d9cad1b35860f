#pragma once
// The trainee app (`ikebana` with no subcommand): the default scene in a stereo window. Haptic devices
// if present, else the window's mouse and keyboard as both hands (Tab switches, left button grabs,
// Shift or the wheel for depth). The arrow keys or a right-button drag orbit the camera during
// training, and the hands' workspace turns with it so that "forward" stays away from the viewer.
// Escape or closing the window ends the session. With no display it renders offscreen instead and
// says where the images went.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

struct GLFWwindow;

namespace ikebana::platform {
class PointerSource;
}

namespace ikebana::game {

struct TraineeAppOptions {
    std::string scene;
    std::string lesson; // a lesson id or file: its scene, its keys, and Enter scores against its form
    std::string left_device = "auto";
    std::string right_device = "auto";
    std::vector<std::string> env;
    std::vector<std::string> rates; // "name=hz" over the scene's rates (render=60: frames at 60 Hz)
    std::uint32_t msaa = 0;     // anti-aliasing samples (0: automatic, window_stack.hpp)
    bool full_detail = false;   // every mesh as modelled, however small on screen (no coarse copies)
    std::string stereo;         // empty: the scene's "display"
    std::uint32_t width = 1280; // the window
    std::uint32_t height = 720;
    std::uint32_t frames = 0;   // stop after this many presented frames (0: until closed)
    std::string screenshot;     // write the last presented frame here (PNG)
#ifdef NDEBUG
    bool validation = false;
#else
    bool validation = true; // the validation layer is always on in debug builds
#endif
    std::uint32_t finish_at_frame = 0; // as if Enter were pressed then (tests, demos)
    // Each frame, what the window shows as data (game/session/window_state.hpp), for a script that works
    // the window from outside (`ikebana lesson demo --window`). Empty: not written.
    std::string state_out;
    // Where each scored lesson session is stored (game/progress/progress_db.hpp); empty: nowhere
    // (tests that run the app in-process store nothing unless they ask).
    std::string progress_db;
    std::string trainee;        // empty: the name the database remembers, else $USER
    bool demonstration = false; // the sessions are a teacher's demonstration (lesson demo --window)
    // The session's figures (threads' lateness, frame times): printed at the end with `stats`, else
    // written to `log_path` (empty: nowhere), not on a trainee's terminal.
    bool stats = false;
    // Open on the start screen (the lessons, the trainee's name and results); a lesson's Esc comes
    // back to it. Off: straight into --lesson or --scene, and Esc ends.
    bool start_screen = false;
    std::string log_path;
    // Called before each frame with the frames presented so far (tests drive the window with it:
    // resize it, minimise it). Nothing when empty.
    std::function<void(std::uint32_t presented, GLFWwindow* window)> each_frame;
    // The mouse and keyboard the hands follow when no device drives them: the window's own when null
    // (tests and replays put a scripted pointer here).
    platform::PointerSource* pointer = nullptr;
};

int run_trainee_app(const TraineeAppOptions& options);

} // namespace ikebana::game
