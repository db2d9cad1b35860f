#pragma once
// How a flower looks (the species says; the renderer only draws what the presentation systems list).
#include <string>

#include <glm/glm.hpp>

namespace ikebana::components {

struct FlowerLook {
    std::string head_mesh;   // glTF relative to assets/, empty: no head
    glm::vec3 stem_colour;   // linear RGB
    glm::vec3 petal_colour;
    glm::vec3 leaf_colour;
    glm::vec3 head_colour;
};

} // namespace ikebana::components
