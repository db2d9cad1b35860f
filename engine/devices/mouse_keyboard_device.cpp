#include "engine/devices/mouse_keyboard_device.hpp"

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

MouseKeyboardHands::MouseKeyboardHands(platform::PointerSource& source, Config config) : source_(source), config_(config) {}

std::unique_ptr<HapticDevice> MouseKeyboardHands::hand(std::uint8_t which) { return std::make_unique<MouseHand>(*this, which & 1u); }

void MouseKeyboardHands::update(std::int64_t now_us) {
    if (now_us == last_update_us_) return;
    last_update_us_ = now_us;
    const platform::PointerState now = source_.read();
    if (now.switch_hand && !tab_was_down_) active_ ^= 1u;
    tab_was_down_ = now.switch_hand;
    // A right-button drag turns the camera; the hand stays where it is meanwhile.
    // The cursor's motion since the last reading (up to where the reader put it back in the middle).
    // The same reading again (the window reads the mouse once a frame, the hands a thousand times a
    // second) has not moved; a warp counts once.
    const bool same_reading = now.cursor_px == last_.cursor_px && now.warped_from_px == last_.warped_from_px;
    const glm::dvec2 moved = same_reading ? glm::dvec2{0.0} : (now.warped_from_px.x >= 0.0 ? now.warped_from_px : now.cursor_px) - last_.cursor_px;
    if (started_ && !now.orbit_button && now.tilt_modifier) {
        // Ctrl: the hand stays, the held stem turns about the grip (right: its top to the right; up:
        // its top away from the viewer; the wheel: about the vertical).
        glm::dvec3& r = rotation_[active_];
        r.y += moved.x / now.window_px.x * config_.tilt_per_window_rad;
        r.x -= moved.y / now.window_px.y * config_.tilt_per_window_rad;
        r.z += (now.scroll - last_.scroll) * config_.turn_per_scroll_rad;
        r = glm::clamp(r, glm::dvec3{-6.0}, glm::dvec3{6.0});
    } else if (started_ && !now.orbit_button) {
        const double mx = moved.x / now.window_px.x * config_.workspace_width_m;
        const double my = -moved.y / now.window_px.y * config_.workspace_height_m; // screen y grows downwards
        glm::dvec3& p = position_[active_];
        p.x += mx;
        if (now.depth_modifier) p.y += my;
        else p.z += my;
        p.y += (now.scroll - last_.scroll) * config_.depth_per_scroll_m;
        p = glm::clamp(p, config_.reach_min_m, config_.reach_max_m);
    }
    buttons_[active_] = now.grab_button ? 1u : 0u;
    last_ = now;
    started_ = true;
}

DeviceSample MouseKeyboardHands::sample(std::uint8_t which, std::int64_t now_us) const {
    DeviceSample s;
    s.time_us = now_us;
    s.position = position_[which & 1u];
    s.buttons = buttons_[which & 1u];
    s.rotation = rotation_[which & 1u];
    return s;
}

} // namespace ikebana::devices
