#pragma once
// Heads-up text as triangles, from stb_easy_font (no font files, no atlas): a translucent panel with
// lines of text, in the output's pixels. The renderer draws it on top of the composed frame, once per
// eye's area so that it sits at screen depth in every stereo mode.
#include <cstdint>
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
};

// Triangles in unscaled pixels relative to the panel's origin (the scale and origin are applied when
// drawn). Empty when there are no lines.
std::vector<OverlayVertex> overlay_triangles(const OverlayPanel& panel);

} // namespace ikebana::render
