#pragma once
// The trainee window's pointer aimed through its camera: each reading gets the ray under the cursor
// (PointerState::ray, in the hands' device space), so that the hand the mouse drives moves as the
// point under the cursor does, at the hand's depth, in whichever eye's image the cursor is. And the
// cursor is put back on that hand whenever the hand has gone from under it: at the start, after Tab
// (the other hand), after a Ctrl or Shift drag (the hand stayed, or went in depth, while the cursor
// moved), after the camera turned, when the cursor crosses into the other eye's image, and when it
// rests away from a hand that could not follow it (at the edge of its reach, on the table).
#include <array>
#include <cstdint>
#include <functional>
#include <optional>

#include <glm/glm.hpp>

#include "components/snapshot.hpp"
#include "engine/platform/pointer_input.hpp"
#include "engine/render/screen_layout.hpp"
#include "engine/render/stereo_camera.hpp"
#include "engine/render/stereo_renderer.hpp"

namespace ikebana::game {

// The camera as the window draws this frame. The hands' device space is the world turned by the
// camera's yaw about the vertical (WorkspaceMapping: centre 0, scale 1, as World::create makes it).
struct PointerView {
    render::StereoRig rig; // orbited, as drawn
    render::StereoMode mode = render::StereoMode::side_by_side;
    double yaw_rad = 0.0;
    double column_px = 0.0; // kept right of each eye's scene for panels (render::ScreenLayout)
    [[nodiscard]] render::ScreenLayout layout(glm::dvec2 window_px) const { return {mode, window_px, column_px}; }
};

// Which eye's image a window pixel is in (-1 left, 1 right; 0 when one image shows both) and where in
// it (uv, [0, 1] inside the scene); the rig with that image's aspect.
struct EyeSpot {
    int eye = 0;
    glm::dvec2 uv{0.5};
};
[[nodiscard]] EyeSpot eye_spot(const render::ScreenLayout& layout, glm::dvec2 cursor_px);
[[nodiscard]] render::StereoRig rig_for_window(render::StereoRig rig, const render::ScreenLayout& layout);
// The ray under a window pixel, in device space.
[[nodiscard]] platform::PointerRay pointer_ray(const PointerView& view, glm::dvec2 window_px, glm::dvec2 cursor_px);
// Where an eye shows a world point, in window pixels (nothing: behind it).
[[nodiscard]] std::optional<glm::dvec2> drawn_px(const PointerView& view, glm::dvec2 window_px, int eye, const glm::dvec3& world_m);
// Window pixels per metre sideways and up at a world point, as an eye shows it.
[[nodiscard]] std::optional<glm::dvec2> px_per_m_at(const PointerView& view, glm::dvec2 window_px, int eye, const glm::dvec3& world_m);

// What the mouse's hands need to know of the stem the active hand holds, from the newest frame: where
// it is held fast when it stands in the pins (PointerState::turn_about: a lean turns it about its
// bottom there) and which way it points (lean_along: a lean moves its tip the way asked), in device
// space (the world turned back by the camera's yaw). Both cleared when it holds nothing.
void tell_held_stem(platform::PointerState& in, const components::FrameSnapshot& frame, std::uint8_t hand, double view_yaw_rad);

// Pick by ray: where the open hand the mouse drives goes (device space) with this reading, when it is to
// go onto the stem drawn under the cursor: the nearest stem or twig along the ray through the cursor
// (systems::stem_under_ray), met where the ray passes its axis, so the cube sits on it under the
// cursor. Asked when the cursor moved (and the wheel did not: a notch is the trainee's own depth, kept
// until the cursor next moves) with the button up, or with the press itself; never while the hand
// holds a stem, with Ctrl or Shift down, or without a ray. `was`: the reading the hands last got.
[[nodiscard]] std::optional<glm::dvec3> hand_onto_stem_under_cursor(const platform::PointerState& in, const platform::PointerState& was, bool press,
                                                                    const components::FrameSnapshot& frame, std::uint8_t hand, double view_yaw_rad);

class PointerAim {
public:
    explicit PointerAim(std::uint8_t active_hand = 1) : active_(active_hand & 1u) {}
    // Fills in the rays; moves the cursor (through put_cursor, and in `in`) onto the hand the mouse
    // drives when it is to go back there. `hands_m`: where the hands' devices put them in the world
    // (the window's newest frame; nothing for a hand it does not show).
    void aim(platform::PointerState& in, const PointerView& view, const std::array<std::optional<glm::dvec3>, 2>& hands_m,
             const std::function<void(glm::dvec2)>& put_cursor);
    // The hand the mouse drives, as this reader follows Tab (the hands follow the same readings).
    [[nodiscard]] std::uint8_t active_hand() const noexcept { return active_; }

private:
    bool started_ = false;
    bool tab_was_down_ = false;
    bool was_held_ = false;       // a modifier, the right button or an arrow was down at the last reading
    std::uint8_t active_ = 1;     // the right hand first, as MouseKeyboardHands
    int last_eye_ = 0;
    glm::dvec2 last_cursor_px_{0.0};
    std::optional<glm::dvec2> put_at_px_; // where it last put the cursor (none yet: it goes onto the hand once the hand shows)
    int settle_ = 0;              // readings left to put it there again, from newer frames
    int still_ = 0;               // readings the cursor has not moved
};

} // namespace ikebana::game
