#include "game/app/window_camera.hpp"

#include <algorithm>

namespace ikebana::game {

void WindowCamera::reset(const render::StereoRig& base) {
    base_ = base;
    yaw_rad_ = pitch_rad_ = 0.0;
    presses_seen_.reset();
    dragging_ = false;
}

void WindowCamera::turn(const platform::PointerState& in) {
    constexpr double yaw_step_rad = 15.0 * 3.14159265358979323846 / 180.0;
    constexpr double pitch_step_rad = 10.0 * 3.14159265358979323846 / 180.0;
    // Presses made before the first reading (typed on the start screen) turn nothing.
    const glm::dvec2 pressed = presses_seen_ ? in.arrow_presses - *presses_seen_ : glm::dvec2{0.0};
    presses_seen_ = in.arrow_presses;
    yaw_rad_ += yaw_step_rad * pressed.x;
    pitch_rad_ += pitch_step_rad * pressed.y;
    if (in.orbit_button) {
        if (dragging_) {
            yaw_rad_ += 0.005 * (in.cursor_px.x - drag_from_px_.x);
            pitch_rad_ += 0.005 * (in.cursor_px.y - drag_from_px_.y);
        }
        dragging_ = true;
        drag_from_px_ = in.cursor_px;
    } else {
        dragging_ = false;
    }
    pitch_rad_ = std::clamp(pitch_rad_, -0.5, 1.0);
}

render::StereoRig WindowCamera::rig() const { return render::orbited(base_, yaw_rad_, pitch_rad_); }

} // namespace ikebana::game
