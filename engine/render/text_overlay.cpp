#include "engine/render/text_overlay.hpp"

#include <algorithm>
#include <cmath>

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wconversion"
#pragma GCC diagnostic ignored "-Wsign-conversion"
#pragma GCC diagnostic ignored "-Wshadow"
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#include <stb_easy_font.h>
#pragma GCC diagnostic pop

namespace ikebana::render {

namespace {
std::uint8_t byte(float v) { return static_cast<std::uint8_t>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f)); }

void quad_as_triangles(std::vector<OverlayVertex>& out, const OverlayVertex* q) {
    for (int k : {0, 1, 2, 0, 2, 3}) out.push_back(q[k]);
}
} // namespace

std::vector<OverlayVertex> overlay_triangles(const OverlayPanel& panel) {
    std::vector<OverlayVertex> out;
    if (panel.lines.empty()) return out;
    const float line_height = 12.0f;
    float width = 0.0f;
    for (const auto& line : panel.lines) width = std::max(width, static_cast<float>(stb_easy_font_width(const_cast<char*>(line.c_str()))));
    const float pad = 4.0f;
    const float height = line_height * static_cast<float>(panel.lines.size());
    const std::uint8_t pc[4] = {byte(panel.panel_colour.r), byte(panel.panel_colour.g), byte(panel.panel_colour.b), byte(panel.panel_colour.a)};
    const OverlayVertex background[4] = {{-pad, -pad, 0, {pc[0], pc[1], pc[2], pc[3]}},
                                         {width + pad, -pad, 0, {pc[0], pc[1], pc[2], pc[3]}},
                                         {width + pad, height + pad, 0, {pc[0], pc[1], pc[2], pc[3]}},
                                         {-pad, height + pad, 0, {pc[0], pc[1], pc[2], pc[3]}}};
    quad_as_triangles(out, background);
    unsigned char tc[4] = {byte(panel.text_colour.r), byte(panel.text_colour.g), byte(panel.text_colour.b), byte(panel.text_colour.a)};
    std::vector<OverlayVertex> quads;
    for (std::size_t i = 0; i < panel.lines.size(); ++i) {
        std::string text = panel.lines[i];
        // About 270 bytes of vertices per character is stb_easy_font's documented worst case.
        quads.resize(text.size() * 300 / sizeof(OverlayVertex) + 16);
        const int n = stb_easy_font_print(0.0f, line_height * static_cast<float>(i), text.data(), tc, quads.data(),
                                          static_cast<int>(quads.size() * sizeof(OverlayVertex)));
        for (int q = 0; q < n; ++q) quad_as_triangles(out, &quads[static_cast<std::size_t>(q) * 4]);
    }
    return out;
}

glm::vec2 overlay_extent_px(const OverlayPanel& panel) {
    if (panel.lines.empty()) return glm::vec2{0.0f};
    float width = 0.0f;
    for (const auto& line : panel.lines) width = std::max(width, static_cast<float>(stb_easy_font_width(const_cast<char*>(line.c_str()))));
    return panel.scale * glm::vec2{width + 8.0f, 12.0f * static_cast<float>(panel.lines.size()) + 8.0f};
}

std::optional<glm::vec2> overlay_origin_px(const OverlayPanel& panel, const glm::mat4& view_projection, glm::vec2 eye_size_px) {
    if (!panel.anchor_m) return panel.origin_px;
    const glm::vec4 clip = view_projection * glm::vec4(*panel.anchor_m, 1.0f);
    if (clip.w <= 1e-6f) return std::nullopt;
    // Vulkan's clip y points down, as pixel rows do.
    const glm::vec2 seen = (glm::vec2(clip.x, clip.y) / clip.w * 0.5f + 0.5f) * eye_size_px;
    const glm::vec2 size = overlay_extent_px(panel);
    // The panel's padding is drawn around its origin (4 unscaled pixels each way).
    glm::vec2 origin = seen + glm::vec2{-0.5f * size.x, -size.y} + glm::vec2{4.0f * panel.scale};
    // Kept whole in the eye's image sideways (a label cut at the edge cannot be read).
    origin.x = std::clamp(origin.x, 4.0f * panel.scale, std::max(4.0f * panel.scale, eye_size_px.x - size.x + 4.0f * panel.scale));
    return origin;
}

} // namespace ikebana::render
