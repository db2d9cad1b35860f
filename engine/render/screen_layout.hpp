#pragma once
// Where a window's scene goes beside its panels, in every stereo mode. The window is laid out in
// areas: side by side, one per eye (each half; the display stretches each to the whole screen for its
// eye), otherwise one (the whole window; interleaved rows, anaglyph and mono put both eyes in the same
// pixels). Each area keeps a column on its right for text and controls, and the scene is drawn in the
// rest, so no text ever covers it. The renderer, the pointer's aim and the window's layout report all
// take their numbers from here.
#include <algorithm>
#include <cstdint>

#include <glm/glm.hpp>

#include "engine/render/stereo_renderer.hpp"

namespace ikebana::render {

struct ScreenLayout {
    StereoMode mode = StereoMode::mono;
    glm::dvec2 window_px{1.0};
    double column_px = 0.0; // reserved on the right of each area

    [[nodiscard]] int areas() const noexcept { return mode == StereoMode::side_by_side ? 2 : 1; }
    [[nodiscard]] double area_width_px() const noexcept { return std::max(1.0, window_px.x) / areas(); }
    // The scene's part of an area (never narrower than a sixteenth of it, whatever the column asks).
    [[nodiscard]] double scene_width_px() const noexcept {
        return std::max(area_width_px() / 16.0, std::max(1.0, area_width_px() - std::max(0.0, column_px)));
    }
    [[nodiscard]] double height_px() const noexcept { return std::max(1.0, window_px.y); }
    // Where the eye's scene starts: -1 the left eye, 1 the right, 0 the one image both share.
    [[nodiscard]] double scene_left_px(int eye) const noexcept { return areas() == 2 && eye > 0 ? area_width_px() : 0.0; }
    // The eye whose scene (or column) a window pixel is in (0 when one image shows both).
    [[nodiscard]] int eye_at(glm::dvec2 px) const noexcept {
        if (areas() == 1) return 0;
        return px.x < area_width_px() ? -1 : 1;
    }
    // The pixel is in the scene (not in a column, not off the window).
    [[nodiscard]] bool in_scene(glm::dvec2 px) const noexcept {
        const double local = px.x - scene_left_px(eye_at(px));
        return local >= 0.0 && local < scene_width_px() && px.y >= 0.0 && px.y < height_px();
    }
    // A window pixel as a point in its eye's scene image, [0, 1] inside it.
    [[nodiscard]] glm::dvec2 scene_uv(glm::dvec2 px) const noexcept {
        return {(px.x - scene_left_px(eye_at(px))) / scene_width_px(), px.y / height_px()};
    }
    [[nodiscard]] glm::dvec2 window_px_of(int eye, glm::dvec2 uv) const noexcept {
        return {scene_left_px(eye) + uv.x * scene_width_px(), uv.y * height_px()};
    }
    // The eye image's width-to-height ratio (the camera's aspect).
    [[nodiscard]] double aspect() const noexcept { return scene_width_px() / height_px(); }
};

} // namespace ikebana::render
