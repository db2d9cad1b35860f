#include "game/app/panel_pointer.hpp"

namespace ikebana::game {

void PanelPointer::in_scene(platform::PointerState& in) {
    wheel_seen_ = in.scroll;
    in.scroll -= wheel_over_panel_;
    if (held_over_panel_ && in.grab_button) held_over_panel_ = false; // a press back in the scene: its release lets go
    if (held_over_panel_) in.grab_button = true;
}

void PanelPointer::over_panel(const platform::PointerState& in) {
    wheel_over_panel_ += in.scroll - wheel_seen_;
    wheel_seen_ = in.scroll;
    if (last_.grab_button && !in.grab_button) held_over_panel_ = true;
    last_.switch_hand = in.switch_hand;
    last_.view_yaw_rad = in.view_yaw_rad;
    last_.tilt_presses = in.tilt_presses;
    last_.turn_about = in.turn_about; // the panel's lean buttons turn it as Ctrl+arrows do
    last_.turn_about_m = in.turn_about_m;
    last_.lean_along = in.lean_along;
    last_.lean_along_dir = in.lean_along_dir;
    // Back in the scene the hand goes on from where the cursor comes in, not from where it left.
    last_.ray_before = last_.ray;
    last_.warped_from_px = glm::dvec2{-1.0};
}

} // namespace ikebana::game
