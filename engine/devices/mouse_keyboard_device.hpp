#pragma once
// Two hands from one mouse and keyboard, for trainees with no haptic device. The mouse drives the
// active hand; Tab switches hands (the other keeps its place and its grip, so both stay reachable;
// the one switched to keeps its grip, or its open hand, until the button next goes down or up).
// Horizontal motion moves the hand left-right, vertical motion up-down; with Shift held, vertical
// motion moves it in depth instead, and the wheel moves it in depth too. The left button grabs.
// When the pointer comes with a ray through the cursor (PointerState::ray: the window knows its
// camera), the hand moves as the point under the cursor moves at the hand's depth, and the wheel moves
// it along the ray: a hand under the cursor stays under it, in any view. Without one, the window's
// width and height span the Config's workspace.
// With Ctrl held the hand stays and the held stem turns, in the directions the viewer sees: a drag
// right leans its top right, up leans it away from the viewer, the same degrees a pixel whichever way
// it already leans (PointerState::lean_along: the window says which way the held stem points);
// Ctrl+arrows lean it a 5-degree step at a time; Ctrl+wheel swings its lean round the vertical;
// Ctrl+Shift+drag sideways twists it about its own axis.
// When the camera turns (PointerState::view_yaw_rad) the hands stay where they are in the room and
// keep their turn there: turning the camera never moves what a hand holds.
// No force output: the window shows what a force device would make felt.
#include <array>
#include <atomic>
#include <memory>
#include <optional>

#include <glm/gtc/quaternion.hpp>

#include "engine/devices/haptic_device.hpp"
#include "engine/platform/pointer_input.hpp"

namespace ikebana::devices {

class MouseKeyboardHands {
public:
    struct Config {
        double workspace_width_m = 0.30;  // the window's width spans this much (device space)
        double workspace_height_m = 0.25;
        double depth_per_scroll_m = 0.01;
        // Where the hands may go (device space): a table's reach by default; a lesson's is larger.
        glm::dvec3 reach_min_m{-0.15, -0.15, 0.0};
        glm::dvec3 reach_max_m{0.15, 0.15, 0.3};
        double tilt_per_px_rad = 0.25 * 3.14159265358979323846 / 180.0;  // Ctrl+drag: a quarter degree a pixel
        double tilt_step_rad = 5.0 * 3.14159265358979323846 / 180.0;     // Ctrl+arrow
        double turn_per_scroll_rad = 5.0 * 3.14159265358979323846 / 180.0; // Ctrl+wheel, about the vertical
    };
    // The turn one reading of Ctrl makes (device space: x right, y away from the viewer, z up), put
    // before the hand's: the drag's sideways part (px, right positive), then its up-down part (px, down
    // positive), then the wheel's clicks and the arrows' steps (x right, y up = away). Rotations about
    // one axis add up however a motion is split into readings.
    [[nodiscard]] static glm::dquat drag_turn(const Config& config, glm::dvec2 moved_px, double wheel_clicks, glm::dvec2 steps);
    // The same knowing which way the held stem points (`along`, bottom to tip): its tip goes the way
    // asked as the viewer sees it (right; away from the viewer for a drag up or an Up arrow) by the
    // degrees asked on the gauge, whichever way it points now (its lean, tilt toward where it points,
    // moves by that much: a step toward where it already leans adds the step to its tilt), the
    // shortest way (no spin about the stem); the wheel's clicks then swing it round the vertical.
    // Upright, the same as drag_turn. A stem lying to the right leans its tip toward the viewer when
    // asked, where about the fixed axis it only rolled.
    [[nodiscard]] static glm::dquat lean_turn(const Config& config, glm::dvec3 along, glm::dvec2 moved_px, double wheel_clicks, glm::dvec2 steps);
    // Ctrl+Shift+drag sideways, holding a stem that points `along`: it twists about its own axis,
    // right turning its front to the right seen from its tip's side (about +along), the same degrees a
    // pixel as a lean.
    [[nodiscard]] static glm::dquat twist_turn(const Config& config, glm::dvec3 along, double moved_px);
    // The Ctrl gestures that take a hand from one turn to another (DeviceSample::rotation's angles),
    // in whole pixels and clicks, and the angles they reach. Holding nothing (`along` empty): a
    // sideways drag, then an up-down one, then wheel clicks, each in a reading of its own (Euler angles
    // about y, x, z: a small turn is small steps, never a swing out and back); reached within half a
    // click about the vertical. Holding a stem that points `along` (device space, at `from`): a
    // Ctrl+Shift drag of twist_px (twist_turn), then one Ctrl drag of right_px and down_px in one
    // reading (lean_turn), no clicks: reached within the pixels' rounding.
    struct TiltGesture {
        int right_px = 0, down_px = 0, clicks = 0;
        bool held = false; // holding: twist_px first, then right_px and down_px in one drag
        int twist_px = 0;
        glm::dvec3 reached{0.0};
    };
    [[nodiscard]] static TiltGesture tilt_gesture(const Config& config, glm::dvec3 from_angles, glm::dvec3 to_angles,
                                                  std::optional<glm::dvec3> along = std::nullopt);
    explicit MouseKeyboardHands(platform::PointerSource& source) : MouseKeyboardHands(source, Config{}) {}
    MouseKeyboardHands(platform::PointerSource& source, Config config);

    // A device for hand 0 or 1; both share this object (which must outlive them).
    [[nodiscard]] std::unique_ptr<HapticDevice> hand(std::uint8_t which);
    // Read by the window's thread too (its HUD names the hand the mouse drives).
    [[nodiscard]] std::uint8_t active_hand() const noexcept { return active_.load(std::memory_order_relaxed); }
    // Where a hand starts (a scene's hands, near what they are to pick up). Before the session runs.
    void place(std::uint8_t which, glm::dvec3 position_m) { position_[which & 1u] = position_m; }

    // A session started over (the same hands in a new world, before it runs): open hands, unturned,
    // and the next reading the first (nothing carried over: a grip kept after Tab took whatever lay
    // under the hand's start). Where they are stays, for place() to set.
    void restart() {
        started_ = false;
        keep_button_ = false;
        tab_was_down_ = false;
        last_update_us_ = -1;
        buttons_ = {0, 0};
        turn_ = {glm::dquat{1, 0, 0, 0}, glm::dquat{1, 0, 0, 0}};
    }
    // Reads the pointer once per tick, however many hands poll.
    void update(std::int64_t now_us);
    [[nodiscard]] DeviceSample sample(std::uint8_t which, std::int64_t now_us) const;

private:
    platform::PointerSource& source_;
    Config config_;
    std::atomic<std::uint8_t> active_{1}; // the right hand first
    std::int64_t last_update_us_ = -1;
    bool tab_was_down_ = false;
    bool keep_button_ = false; // after Tab: the active hand's button as it was, until the button changes
    bool started_ = false;
    platform::PointerState last_{};
    std::array<glm::dvec3, 2> position_{glm::dvec3{-0.06, 0.0, 0.12}, glm::dvec3{0.06, 0.0, 0.12}};
    std::array<std::uint32_t, 2> buttons_{0, 0};
    std::array<glm::dquat, 2> turn_{glm::dquat{1, 0, 0, 0}, glm::dquat{1, 0, 0, 0}}; // device space
    double yaw_seen_rad_ = 0.0; // the camera's turn at the last reading
};

} // namespace ikebana::devices
