#include "engine/devices/mouse_keyboard_device.hpp"

#include "engine/devices/device_angles.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

namespace ikebana::devices {

namespace {
class MouseHand final : public HapticDevice {
public:
    MouseHand(MouseKeyboardHands& hands, std::uint8_t which) : hands_(hands), which_(which) {
        caps_.name = which ? "mouse and keyboard (right hand)" : "mouse and keyboard (left hand)";
        caps_.has_force_output = false;
        caps_.reports_position = true;
        caps_.workspace_half_extent_m = glm::dvec3{0.15, 0.15, 0.15};
    }
    const DeviceCapabilities& capabilities() const override { return caps_; }
    Result<DeviceSample> poll(std::int64_t now_us) override {
        hands_.update(now_us);
        return hands_.sample(which_, now_us);
    }
    Result<void> send_force(glm::dvec3) override { return {}; }

private:
    MouseKeyboardHands& hands_;
    std::uint8_t which_;
    DeviceCapabilities caps_;
};
} // namespace

namespace {
// The most a lean may reach from the vertical: past it, a stem pointing straight down has no "more".
constexpr double most_lean_rad = 175.0 * 3.14159265358979323846 / 180.0;

// A direction's lean as the trainee reads it on the gauge: its tilt from the vertical, as a length,
// toward where its tip points (x right, y away from the viewer). Round the vertical the map keeps
// tilts exact, so a step toward where a stem already leans adds exactly that step to its tilt.
glm::dvec2 lean_of(const glm::dvec3& d) {
    const double across = std::hypot(d.x, d.y);
    const double tilt = std::atan2(across, d.z);
    if (across > 1e-12) return tilt / across * glm::dvec2{d.x, d.y};
    return d.z > 0.0 ? glm::dvec2{0.0} : glm::dvec2{tilt, 0.0}; // straight down: any way round is as good
}
glm::dvec3 direction_of(const glm::dvec2& lean) {
    const double tilt = glm::length(lean);
    if (tilt < 1e-12) return {0.0, 0.0, 1.0};
    const double s = std::sin(tilt) / tilt;
    return {s * lean.x, s * lean.y, std::cos(tilt)};
}
// The turn that takes one direction to another the shortest way (no spin about either).
glm::dquat shortest_turn(const glm::dvec3& from, const glm::dvec3& to) {
    const glm::dvec3 axis = glm::cross(from, to);
    const double sine = glm::length(axis);
    if (sine < 1e-12) return glm::dquat{1.0, 0.0, 0.0, 0.0}; // the same way (half-turns are capped out by most_lean_rad)
    return glm::angleAxis(std::atan2(sine, glm::dot(from, to)), axis / sine);
}
} // namespace

glm::dquat MouseKeyboardHands::lean_turn(const Config& config, glm::dvec3 along, glm::dvec2 moved_px, double wheel_clicks, glm::dvec2 steps) {
    const double length = glm::length(along);
    if (!(length > 1e-9)) return drag_turn(config, moved_px, wheel_clicks, steps);
    const glm::dquat round = glm::angleAxis(wheel_clicks * config.turn_per_scroll_rad, glm::dvec3{0, 0, 1});
    // The tip goes the way asked as the viewer sees it (right, or away: a drag up, an Up arrow), by the
    // degrees asked on the gauge, whichever way the stem points now: its lean moves that much.
    const glm::dvec3 d = along / length;
    const glm::dvec2 asked{moved_px.x * config.tilt_per_px_rad + steps.x * config.tilt_step_rad, -moved_px.y * config.tilt_per_px_rad + steps.y * config.tilt_step_rad};
    glm::dvec2 to = lean_of(d) + asked;
    if (glm::length(to) > most_lean_rad) to *= most_lean_rad / glm::length(to);
    return round * shortest_turn(d, direction_of(to));
}

glm::dquat MouseKeyboardHands::twist_turn(const Config& config, glm::dvec3 along, double moved_px) {
    const double length = glm::length(along);
    if (!(length > 1e-9)) return glm::dquat{1.0, 0.0, 0.0, 0.0};
    return glm::angleAxis(moved_px * config.tilt_per_px_rad, along / length);
}

glm::dquat MouseKeyboardHands::drag_turn(const Config& config, glm::dvec2 moved_px, double wheel_clicks, glm::dvec2 steps) {
    // Right: the top to the right, about the axis away from the viewer. Up (a negative y in pixels, or
    // an Up arrow): the top away from the viewer, about the axis to the right, negatively.
    const glm::dquat sideways = glm::angleAxis(moved_px.x * config.tilt_per_px_rad + steps.x * config.tilt_step_rad, glm::dvec3{0, 1, 0});
    const glm::dquat away = glm::angleAxis(moved_px.y * config.tilt_per_px_rad - steps.y * config.tilt_step_rad, glm::dvec3{1, 0, 0});
    const glm::dquat round = glm::angleAxis(wheel_clicks * config.turn_per_scroll_rad, glm::dvec3{0, 0, 1});
    return round * away * sideways;
}

MouseKeyboardHands::TiltGesture MouseKeyboardHands::tilt_gesture(const Config& config, glm::dvec3 from_angles, glm::dvec3 to_angles,
                                                                 std::optional<glm::dvec3> along) {
    const glm::dquat from = turn_of_angles(from_angles);
    const glm::dquat to = turn_of_angles(to_angles);
    TiltGesture g;
    if (along && glm::length(*along) > 1e-9) {
        // Holding a stem: the drag that takes its tip where the turn puts it (as lean_turn leans it), and
        // before it the twist about its own axis that leaves it turned as asked about that axis too (a
        // twist leaves the stem pointing where it pointed, so the drag is worked out from there).
        g.held = true;
        const glm::dvec3 d0 = glm::normalize(*along);
        const glm::dquat whole = glm::normalize(to * glm::conjugate(from));
        const glm::dvec2 asked = lean_of(whole * d0) - lean_of(d0);
        g.right_px = static_cast<int>(std::lround(asked.x / config.tilt_per_px_rad));
        g.down_px = static_cast<int>(std::lround(-asked.y / config.tilt_per_px_rad));
        const glm::dquat lean = lean_turn(config, d0, {g.right_px, g.down_px}, 0.0, {});
        const glm::dquat rest = glm::normalize(glm::conjugate(lean) * whole); // about d0, but for the pixels' rounding
        const double twist = 2.0 * std::atan2(glm::dot(glm::dvec3{rest.x, rest.y, rest.z}, d0), rest.w);
        g.twist_px = static_cast<int>(std::lround(std::remainder(twist, 2.0 * 3.14159265358979323846) / config.tilt_per_px_rad));
        g.reached = angles_of_turn(lean * twist_turn(config, d0, g.twist_px) * from);
        return g;
    }
    // The turn to make, as drag_turn composes it: Rz(round) Rx(away) Ry(sideways).
    const glm::dmat3 m = glm::mat3_cast(glm::normalize(to * glm::conjugate(from))); // m[column][row]
    const double away = std::asin(std::clamp(m[1][2], -1.0, 1.0));
    const double sideways = std::atan2(-m[0][2], m[2][2]);
    const double round = std::atan2(-m[1][0], m[1][1]);
    g.right_px = static_cast<int>(std::lround(sideways / config.tilt_per_px_rad));
    g.down_px = static_cast<int>(std::lround(away / config.tilt_per_px_rad));
    g.clicks = static_cast<int>(std::lround(round / config.turn_per_scroll_rad));
    g.reached = angles_of_turn(drag_turn(config, {0, 0}, g.clicks, {}) * drag_turn(config, {0, g.down_px}, 0.0, {}) *
                               drag_turn(config, {g.right_px, 0}, 0.0, {}) * from);
    return g;
}

MouseKeyboardHands::MouseKeyboardHands(platform::PointerSource& source, Config config) : source_(source), config_(config) {}

std::unique_ptr<HapticDevice> MouseKeyboardHands::hand(std::uint8_t which) { return std::make_unique<MouseHand>(*this, which & 1u); }

void MouseKeyboardHands::update(std::int64_t now_us) {
    if (now_us == last_update_us_) return;
    last_update_us_ = now_us;
    const platform::PointerState now = source_.read();
    if (now.switch_hand && !tab_was_down_) {
        active_.store(active_.load(std::memory_order_relaxed) ^ 1u, std::memory_order_relaxed);
        // The hand switched to keeps its button as it left it until the button next goes down or up:
        // Tab back to a hand holding a stem, with the button up, dropped the stem (a first-timer's
        // hikae fell onto the table with no word).
        keep_button_ = true;
    }
    const std::uint8_t active = active_.load(std::memory_order_relaxed);
    tab_was_down_ = now.switch_hand;
    // A right-button drag turns the camera; the hand stays where it is meanwhile.
    // The cursor's motion since the last reading (up to where the reader put it back in the middle).
    // The same reading again (the window reads the mouse once a frame, the hands a thousand times a
    // second) has not moved; a warp counts once.
    const bool same_reading = now.cursor_px == last_.cursor_px && now.warped_from_px == last_.warped_from_px;
    const glm::dvec2 moved = same_reading ? glm::dvec2{0.0} : (now.warped_from_px.x >= 0.0 ? now.warped_from_px : now.cursor_px) - last_.cursor_px;
    // Where a ray meets the upright plane at depth y (device space); nothing if it runs along it.
    const auto at_depth = [](const platform::PointerRay& ray, double y) -> std::optional<glm::dvec3> {
        if (!ray.valid || std::abs(ray.direction.y) < 1e-6) return std::nullopt;
        const double t = (y - ray.origin_m.y) / ray.direction.y;
        if (t <= 0.0) return std::nullopt;
        return ray.origin_m + t * ray.direction;
    };
    // This reading's motion was counted already (the same reading again): the cursor is where it was.
    const platform::PointerRay& from_ray = same_reading ? now.ray : now.ray_before;
    const bool aimed = now.ray.valid && from_ray.valid && now.ray.eye == from_ray.eye;
    const double wheel = now.scroll - last_.scroll;
    // The camera turned: both hands stay where they are in the room, turned as they were there (device
    // space turns with the camera: the world is the device space turned by the yaw).
    if (started_ && now.view_yaw_rad != yaw_seen_rad_) {
        const glm::dquat back = glm::angleAxis(-(now.view_yaw_rad - yaw_seen_rad_), glm::dvec3{0, 0, 1});
        for (std::size_t h = 0; h < 2; ++h) {
            position_[h] = back * position_[h];
            turn_[h] = back * turn_[h] * glm::conjugate(back);
        }
    }
    yaw_seen_rad_ = now.view_yaw_rad;
    // A turn of the active hand: about its grip, or about where the window says its stem is held fast
    // (the hand goes round that point as the stem turns).
    const auto turn_by = [&](const glm::dquat& by) {
        turn_[active] = glm::normalize(by * turn_[active]);
        if (now.turn_about) position_[active] = glm::clamp(now.turn_about_m + by * (position_[active] - now.turn_about_m), config_.reach_min_m, config_.reach_max_m);
    };
    // A lean asked for (Ctrl+drag, Ctrl+arrows, the panel's buttons): knowing which way the held stem
    // points, its tip moved the way asked (lean_turn); holding nothing, about fixed axes as the viewer
    // sees them.
    const auto lean = [&](glm::dvec2 moved_px, double wheel_clicks, glm::dvec2 arrow_steps) {
        return now.lean_along ? lean_turn(config_, now.lean_along_dir, moved_px, wheel_clicks, arrow_steps) : drag_turn(config_, moved_px, wheel_clicks, arrow_steps);
    };
    // Ctrl+arrows lean the held stem a step, in or out of a drag.
    const glm::dvec2 steps = started_ ? now.tilt_presses - last_.tilt_presses : glm::dvec2{0.0};
    if (steps != glm::dvec2{0.0}) turn_by(lean({0.0, 0.0}, 0.0, steps));
    if (started_ && !now.orbit_button && now.tilt_modifier) {
        // Ctrl: the held stem turns, as the viewer sees it; the hand stays (or goes round the point
        // its stem is held at).
        // With Shift too, a held stem twists about its own axis as a drag goes sideways (turned between
        // the fingers: where a bend or a branch faces), pointing where it pointed.
        if (now.depth_modifier && now.lean_along) {
            if (moved.x != 0.0) turn_by(twist_turn(config_, now.lean_along_dir, moved.x));
        } else if (moved != glm::dvec2{0.0} || wheel != 0.0) {
            turn_by(lean(moved, wheel, {0.0, 0.0}));
        }
    } else if (started_ && !now.orbit_button && now.ray.valid) {
        // The cursor went into the other eye's image, or runs along the hand's plane: the hand stays (the
        // window puts the cursor back on it).
        glm::dvec3& p = position_[active];
        const auto was = aimed ? at_depth(from_ray, p.y) : std::nullopt;
        const auto is = aimed ? at_depth(now.ray, p.y) : std::nullopt;
        if (was && is && now.depth_modifier) {
            // Shift: the cursor's way up at the hand's depth takes the hand that far away from the viewer.
            p.x += is->x - was->x;
            p.y += is->z - was->z;
        } else if (was && is) {
            // Under the cursor at its depth (the wheel's depth), as far off it as it was.
            const double y = p.y + wheel * config_.depth_per_scroll_m;
            if (const auto there = at_depth(now.ray, y)) p = *there + (p - *was);
            else p += *is - *was;
        }
        p = glm::clamp(p, config_.reach_min_m, config_.reach_max_m);
    } else if (started_ && !now.orbit_button) {
        const double mx = moved.x / now.window_px.x * config_.workspace_width_m;
        const double my = -moved.y / now.window_px.y * config_.workspace_height_m; // screen y grows downwards
        glm::dvec3& p = position_[active];
        p.x += mx;
        if (now.depth_modifier) p.y += my;
        else p.z += my;
        p.y += wheel * config_.depth_per_scroll_m;
        p = glm::clamp(p, config_.reach_min_m, config_.reach_max_m);
    }
    // Put somewhere by the window (before the button is taken: a press that moved it takes it there).
    if (started_ && now.hand_moves != last_.hand_moves) position_[active] = glm::clamp(now.hand_to_m, config_.reach_min_m, config_.reach_max_m);
    if (keep_button_ && now.grab_button != last_.grab_button) keep_button_ = false;
    if (!keep_button_) buttons_[active] = now.grab_button ? 1u : 0u;
    last_ = now;
    started_ = true;
}

DeviceSample MouseKeyboardHands::sample(std::uint8_t which, std::int64_t now_us) const {
    DeviceSample s;
    s.time_us = now_us;
    s.position = position_[which & 1u];
    s.buttons = buttons_[which & 1u];
    s.rotation = angles_of_turn(turn_[which & 1u]);
    return s;
}

} // namespace ikebana::devices
