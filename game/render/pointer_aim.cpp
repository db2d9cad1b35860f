#include "game/render/pointer_aim.hpp"

#include <cmath>

#include "systems/presentation/draw_list.hpp"

namespace ikebana::game {

namespace {
// A resting cursor this far from the hand it drives (window pixels), after this many readings at rest,
// goes back onto the hand.
constexpr double stray_px = 20.0;
constexpr int readings_to_catch_up = 3;

// Device space from world space and back: turned by the camera's yaw about the vertical.
glm::dvec3 turned(const glm::dvec3& v, double yaw) {
    const double c = std::cos(yaw), s = std::sin(yaw);
    return {c * v.x - s * v.y, s * v.x + c * v.y, v.z};
}
} // namespace

void tell_held_stem(platform::PointerState& in, const components::FrameSnapshot& frame, std::uint8_t hand, double view_yaw_rad) {
    in.turn_about = false;
    in.lean_along = false;
    const auto& h = frame.hands[hand & 1u];
    if (!h.holding || h.held_flower < 0 || static_cast<std::size_t>(h.held_flower) >= frame.flowers.size()) return;
    const auto& f = frame.flowers[static_cast<std::size_t>(h.held_flower)];
    if (f.in_kenzan && !f.points_m.empty()) {
        in.turn_about = true;
        in.turn_about_m = turned(f.points_m.front(), -view_yaw_rad);
    }
    if (f.points_m.size() >= 2 && glm::length(f.points_m.back() - f.points_m.front()) > 1e-6) {
        in.lean_along = true;
        in.lean_along_dir = turned(glm::normalize(f.points_m.back() - f.points_m.front()), -view_yaw_rad);
    }
}

EyeSpot eye_spot(const render::ScreenLayout& layout, glm::dvec2 cursor_px) {
    return {layout.eye_at(cursor_px), layout.scene_uv(cursor_px)};
}

render::StereoRig rig_for_window(render::StereoRig rig, const render::ScreenLayout& layout) {
    rig.aspect = layout.aspect();
    if (layout.mode == render::StereoMode::mono) rig.eye_separation_m = 0.0;
    return rig;
}

platform::PointerRay pointer_ray(const PointerView& view, glm::dvec2 window_px, glm::dvec2 cursor_px) {
    const auto layout = view.layout(window_px);
    const EyeSpot spot = eye_spot(layout, cursor_px);
    const render::ViewRay ray = render::eye_ray(rig_for_window(view.rig, layout), spot.eye, spot.uv);
    platform::PointerRay out;
    out.origin_m = turned(ray.origin_m, -view.yaw_rad);
    out.direction = turned(ray.direction, -view.yaw_rad);
    out.eye = spot.eye;
    out.valid = true;
    return out;
}

std::optional<glm::dvec2> drawn_px(const PointerView& view, glm::dvec2 window_px, int eye, const glm::dvec3& world_m) {
    const auto layout = view.layout(window_px);
    const auto uv = render::eye_uv(rig_for_window(view.rig, layout), eye, world_m);
    if (!uv) return std::nullopt;
    return layout.window_px_of(eye, *uv);
}

std::optional<glm::dvec2> px_per_m_at(const PointerView& view, glm::dvec2 window_px, int eye, const glm::dvec3& world_m) {
    const double step = 0.01;
    const auto at = drawn_px(view, window_px, eye, world_m);
    const auto right = drawn_px(view, window_px, eye, world_m + turned({step, 0.0, 0.0}, view.yaw_rad));
    const auto up = drawn_px(view, window_px, eye, world_m + glm::dvec3{0.0, 0.0, step});
    if (!at || !right || !up) return std::nullopt;
    return glm::dvec2{glm::length(*right - *at), glm::length(*up - *at)} / step;
}

void PointerAim::aim(platform::PointerState& in, const PointerView& view, const std::array<std::optional<glm::dvec3>, 2>& hands_m,
                     const std::function<void(glm::dvec2)>& put_cursor) {
    const bool tab = in.switch_hand && !tab_was_down_;
    tab_was_down_ = in.switch_hand;
    if (tab) active_ ^= 1u;
    // While one of these is down the hand does not follow the cursor (or the view moves under it).
    const bool held = in.tilt_modifier || in.depth_modifier || in.orbit_button || in.arrows != glm::dvec2{0.0};
    const auto layout = view.layout(in.window_px);
    const int eye = eye_spot(layout, in.cursor_px).eye;
    // The trainee moved the cursor since it was put on the hand: no more settling.
    if (put_at_px_ && in.cursor_px != *put_at_px_) settle_ = 0;
    // A cursor that has gone on where the hand could not (past the edge of its reach, into the table)
    // and rests there: once the hand has had readings to catch up, the cursor goes back onto it.
    still_ = started_ && in.cursor_px == last_cursor_px_ ? still_ + 1 : 0;
    bool strayed = false;
    if (const auto& hand = hands_m[active_ & 1u]; hand && still_ >= readings_to_catch_up) {
        const auto px = drawn_px(view, in.window_px, eye, *hand);
        strayed = px && glm::length(*px - in.cursor_px) > stray_px;
    }
    const bool home = !held && (!put_at_px_ || tab || was_held_ || eye != last_eye_ || settle_ > 0 || strayed);
    if (home) {
        if (const auto& hand = hands_m[active_ & 1u]) {
            if (const auto px = drawn_px(view, in.window_px, eye, *hand); px && layout.in_scene(*px)) {
                put_cursor(*px);
                in.cursor_px = *px;
                in.warped_from_px = {-1.0, -1.0};
                // Again for two more readings while nobody moves it: the newest frame may not yet show
                // the hand's last motion.
                settle_ = put_at_px_ && *put_at_px_ == *px ? settle_ - 1 : 2;
                put_at_px_ = *px;
            }
        }
    }
    if (!home && settle_ > 0 && !held) --settle_;
    // A Ctrl+drag tilts by the cursor's motion, which the scene's edge (the window's, or the panels'
    // column) would stop: put back in the middle of its image near an edge, its motion up to there
    // still counted.
    const double margin = 24.0;
    const double left = layout.scene_left_px(eye), right = left + layout.scene_width_px();
    if (in.tilt_modifier && !in.orbit_button && layout.scene_width_px() > 4 * margin && in.window_px.y > 4 * margin &&
        (in.cursor_px.x < left + margin || in.cursor_px.y < margin || in.cursor_px.x > right - margin || in.cursor_px.y > in.window_px.y - margin)) {
        const glm::dvec2 middle{left + 0.5 * layout.scene_width_px(), 0.5 * in.window_px.y};
        put_cursor(middle);
        in.warped_from_px = in.cursor_px;
        in.cursor_px = middle;
    }
    in.ray = pointer_ray(view, in.window_px, in.cursor_px);
    // Where the cursor was, through this reading's camera: a cursor put back (or a turned camera) moves no hand.
    in.ray_before = home || !started_ ? in.ray : pointer_ray(view, in.window_px, last_cursor_px_);
    was_held_ = held;
    last_eye_ = eye_spot(layout, in.cursor_px).eye;
    last_cursor_px_ = in.cursor_px;
    started_ = true;
}

std::optional<glm::dvec3> hand_onto_stem_under_cursor(const platform::PointerState& in, const platform::PointerState& was, bool press,
                                                     const components::FrameSnapshot& frame, std::uint8_t hand, double view_yaw_rad) {
    if (!in.ray.valid || hand >= 2 || frame.hands[hand].holding || in.tilt_modifier || in.depth_modifier) return std::nullopt;
    const bool moved = in.cursor_px != was.cursor_px && !in.grab_button && in.scroll == was.scroll;
    if (!press && !moved) return std::nullopt;
    // Device space is the world turned back by the camera's yaw: the ray turned forward meets the stems.
    const double c = std::cos(view_yaw_rad), s = std::sin(view_yaw_rad);
    const auto to_world = [&](glm::dvec3 v) { return glm::dvec3{c * v.x - s * v.y, s * v.x + c * v.y, v.z}; };
    const auto hit = systems::stem_under_ray(frame, to_world(in.ray.origin_m), to_world(in.ray.direction));
    if (!hit) return std::nullopt;
    return in.ray.origin_m + hit->t_m * glm::normalize(in.ray.direction);
}

} // namespace ikebana::game
