#pragma once
// The teacher's demonstration: a scripted trainee arranges the lesson's model form through the same
// hands, grips, cuts and insertions a trainee uses. It holds both hands' devices (puppets the script
// moves between simulation steps), picks each material off the table, cuts it to length, bends it with
// both hands where the form wants it to rise straight before it leans (a shoka's stems), turns it to
// the role's tilt and direction, pushes it into the kenzan where the role enters it and lets go; then
// the arrangement is measured from the simulation and scored. Nothing places a stem: where the
// physics leaves one is what is scored.
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "engine/core/result.hpp"
#include "engine/devices/haptic_device.hpp"
#include "game/training/form_score.hpp"
#include "game/lesson/lesson.hpp"
#include "game/progress/progress_db.hpp"

namespace ikebana::game {

class World;

struct DemoStep {
    double at_s;       // simulated time the step began
    std::string what;  // "shin: grab the willow_branch", ...
};

struct DemoResult {
    FormScore score;
    std::vector<DemoStep> steps;
    double simulated_s = 0.0;
    std::uint64_t state_hash = 0; // the world's at the end (headless only)
    std::vector<FlowerOutcome> flowers; // how each flower ended (headless only: the window stores its own)
    // The systems' declared access this demonstration did not use (Schedule::unused_access; headless only).
    std::vector<std::string> unused_access;
};

struct DemoOptions {
    // Through the mouse and the lesson's keys, as the window reads them (whole pixels, Shift for
    // depth, Ctrl+drag to tilt, the wheel to turn, C to cut, Enter to score), not a device.
    bool through_mouse = false;
    // With the mouse: also write the session as an xdotool script, to replay against the window.
    std::string xdotool_script;
    // A role held at another tilt than the form's (degrees): how a trainee's mistake scores.
    std::map<std::string, double> tilt_deg;
    // The main stems alone, no supporting stems: a shorter run (the window's, in real time, took more
    // than 10 minutes beside CI with Sogetsu's two jushi); the kenzan rule then fails.
    bool main_stems_only = false;
    // In the window: the progress database the window stores its session in, as a demonstration
    // (empty: it stores nothing).
    std::string window_progress_db;
    std::string record_dir; // headless: the session on record (lesson_session.hpp), for `lesson replay` (empty: none)
    std::function<void(std::size_t done, std::size_t of, const std::string& step)> progress; // each step, as it starts
    // In the window: the window's process, once started (a command stopped by a signal ends it too).
    std::function<void(int pid)> window_started;
};

// A device whose pose a script sets between simulation steps (the demo's hand).
class PuppetDevice final : public devices::HapticDevice {
public:
    struct Pose {
        glm::dvec3 position_m{0.0};
        glm::dvec3 rotation_rad{0.0};
        std::uint32_t buttons = 0;
    };
    explicit PuppetDevice(std::shared_ptr<Pose> pose);
    const devices::DeviceCapabilities& capabilities() const override { return caps_; }
    Result<devices::DeviceSample> poll(std::int64_t now_us) override;
    Result<void> send_force(glm::dvec3) override { return {}; }

private:
    std::shared_ptr<Pose> pose_;
    devices::DeviceCapabilities caps_;
};

Result<DemoResult> run_lesson_demo(const LessonDef& lesson, const DemoOptions& options = {});
// The same teacher working the trainee window from outside, through the X pointer and keyboard
// (xdotool), as a person would: needs an X display. The window's own result (Enter) is returned.
// The tilt options apply; the mouse and xdotool options do not (this is the mouse).
Result<DemoResult> run_lesson_demo_in_window(const LessonDef& lesson, const DemoOptions& options = {});

} // namespace ikebana::game
