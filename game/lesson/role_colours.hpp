#pragma once
// One colour per role of a lesson's form, by the role's place in the lesson (shin, soe, hikae, then
// supporting stems), used wherever a role is drawn or named: the start screen's form sketch and its
// list, the HUD's legend, the G rods and the model arrangement, the markers, the history plot. (The
// start screen once drew soe blue and hikae green while the HUD and the rods drew them green and blue.)
#include <cstddef>
#include <iterator>

#include <glm/glm.hpp>

namespace ikebana::game {

struct RoleColour {
    const char* name; // as the HUD says it ("shin red, soe green, hikae blue")
    glm::vec3 rgb;    // linear, 0-1
};

inline constexpr RoleColour role_colours[] = {{"red", {0.85f, 0.15f, 0.12f}},   {"green", {0.1f, 0.6f, 0.2f}},   {"blue", {0.15f, 0.3f, 0.85f}},
                                              {"orange", {0.9f, 0.55f, 0.1f}}, {"purple", {0.55f, 0.2f, 0.7f}}, {"teal", {0.1f, 0.6f, 0.6f}},
                                              {"brown", {0.5f, 0.3f, 0.15f}},  {"grey", {0.4f, 0.4f, 0.4f}}};

// The colour of the lesson's role number `role` (from 0); past the table it starts again.
constexpr const RoleColour& role_colour(std::size_t role) { return role_colours[role % std::size(role_colours)]; }

} // namespace ikebana::game
