#pragma once
// What the renderer draws in a frame: meshes by name, each with its instances. The renderer knows
// meshes, not flowers; the presentation systems turn the world into this list.
// Built-in meshes: "cube" (unit, centred), "cylinder" (radius 1, from z = 0 to 1; "cylinder_coarse" the
// same with 6 sides instead of 12, for thin things by the hundred), "plane"
// (unit square at z = 0, facing +z); any other name is a glTF file (a missing or broken one is drawn
// as a placeholder, with a warning naming the file).
#include <deque>
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace ikebana::render {

struct MeshInstance {
    glm::mat4 model;
    glm::vec4 colour; // linear RGB, alpha unused
    // Curls the mesh before `model` places it: its +x axis bends toward +z along a circular arc,
    // turning this many radians per unit of x (a cupped petal: one unit long, its tip turned up by
    // this much; negative curls toward -z). 0: drawn as modelled.
    float bend_rad_per_unit = 0.0f;
    float unused[3] = {0.0f, 0.0f, 0.0f}; // to 16 bytes
};

struct DrawBatch {
    std::string mesh;
    std::vector<MeshInstance> instances;
    // Things thinner than a shadow-map texel (the kenzan's pins) cast nothing worth their cost.
    bool casts_shadow = true;
    // Water, ghosts: blended over what is drawn, after it, without hiding what lies behind (no depth
    // write) and without a shadow. Their instances' alpha is their opacity.
    bool translucent = false;
};

struct DrawList {
    // A deque: a batch's reference stays good while others are added (a vector moved them, and a
    // container's wall was written through a dangling reference once a cylinder batch was added).
    std::deque<DrawBatch> batches;
    glm::vec3 light_direction{-0.4f, 0.3f, -1.0f}; // towards which the light shines
    glm::vec3 background{0.93f, 0.92f, 0.88f};
    glm::vec3 shadow_centre{0.0f, 0.0f, 0.1f};     // what the shadow map covers
    float shadow_radius = 0.5f;

    // The batch of this mesh (opaque, or translucent: a mesh may be drawn both ways).
    DrawBatch& batch(const std::string& mesh, bool translucent = false) {
        for (auto& b : batches) {
            if (b.mesh == mesh && b.translucent == translucent) return b;
        }
        return batches.emplace_back(DrawBatch{mesh, {}, !translucent, translucent});
    }

    // Adds another list's instances (its lighting and background are not taken).
    void append(const DrawList& other) {
        for (const auto& b : other.batches) {
            auto& mine = batch(b.mesh, b.translucent);
            mine.casts_shadow = mine.casts_shadow && b.casts_shadow;
            mine.instances.insert(mine.instances.end(), b.instances.begin(), b.instances.end());
        }
    }
};

} // namespace ikebana::render
