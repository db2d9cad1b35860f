#pragma once
// The trainee window's camera: the scene's rig, orbited round the kenzan by the arrow keys (15° round
// or 10° up and down a press, so that eight Left then eight Right come back) and a right-drag (0.005 rad
// a pixel), tilted between -0.5 and 1.0 rad. During training, not only after it (the paper's future
// work). Ctrl+arrows are the held stem's, not the camera's.
#include <optional>

#include <glm/glm.hpp>

#include "engine/platform/pointer_input.hpp"
#include "engine/render/stereo_camera.hpp"

namespace ikebana::game {

class WindowCamera {
public:
    // Back to the scene's own view.
    void reset(const render::StereoRig& base);
    // One frame's reading: the arrows' presses since the last, a right-drag by the cursor's travel.
    void turn(const platform::PointerState& in);
    [[nodiscard]] render::StereoRig rig() const;
    [[nodiscard]] const render::StereoRig& base() const noexcept { return base_; }
    [[nodiscard]] double yaw_rad() const noexcept { return yaw_rad_; }
    [[nodiscard]] double pitch_rad() const noexcept { return pitch_rad_; }

private:
    render::StereoRig base_;
    double yaw_rad_ = 0.0;
    double pitch_rad_ = 0.0;
    glm::dvec2 drag_from_px_{0.0};
    std::optional<glm::dvec2> presses_seen_; // the arrows' count at the last reading (none yet)
    bool dragging_ = false;
};

} // namespace ikebana::game
