#pragma once
// Heads-up text as triangles, from stb_easy_font (no font files, no atlas): a translucent panel with
// lines of text, in the output's pixels. The renderer draws it on top of the composed frame, once per
// eye's area so that it sits at screen depth in every stereo mode.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace ikebana::render {

struct OverlayVertex {
    float x, y, z;
    std::uint8_t colour[4];
};

struct OverlayPanel {
    glm::vec2 origin_px{12.0f, 12.0f}; // top-left, in the eye's image
    float scale = 2.0f;                // stb_easy_font's glyphs are about 6 x 12 px at scale 1
    std::vector<std::string> lines;
    glm::vec4 text_colour{1.0f, 1.0f, 1.0f, 1.0f};
    glm::vec4 panel_colour{0.0f, 0.0f, 0.0f, 0.55f};
    // A label on something in the world: the panel is drawn centred above where this point is seen, in
    // each eye where that eye sees it (so a label has the depth of what it names in stereo), instead of
    // at origin_px; moved sideways as far as it takes to be seen whole. Not drawn in an eye that has
    // the point behind it.
    std::optional<glm::vec3> anchor_m;
};

// The panel's size on screen, its padding included (pixels, scaled).
glm::vec2 overlay_extent_px(const OverlayPanel& panel);

// Where an anchored panel's top-left goes in an eye's image of eye_size_px, given that eye's
// view-projection; nothing when the point is behind the eye. origin_px for a panel without an anchor.
std::optional<glm::vec2> overlay_origin_px(const OverlayPanel& panel, const glm::mat4& view_projection, glm::vec2 eye_size_px);

// Triangles in unscaled pixels relative to the panel's origin (the scale and origin are applied when
// drawn). Empty when there are no lines.
std::vector<OverlayVertex> overlay_triangles(const OverlayPanel& panel);

} // namespace ikebana::render
