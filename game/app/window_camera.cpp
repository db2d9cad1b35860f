#include "game/app/window_camera.hpp"

#include <algorithm>

namespace ikebana::game {

void WindowCamera::reset(const render::StereoRig& base) {
    base_ = base;
    yaw_rad_ = pitch_rad_ = 0.0;
}

void WindowCamera::turn(const platform::PointerState& in) {
    const auto now = std::chrono::steady_clock::now();
    const double dt = std::min(0.1, std::chrono::duration<double>(now - last_).count());
    last_ = now;
    yaw_rad_ += 1.2 * dt * in.arrows.x;
    pitch_rad_ += 1.2 * dt * in.arrows.y;
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
