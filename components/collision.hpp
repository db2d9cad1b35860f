#pragma once
// Collision shapes and the contacts the collision system reports each pass.
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "engine/ecs/entity.hpp"

namespace ikebana::components {

enum class ShapeKind : std::uint8_t { sphere, capsule, box };

// A shape in world space, refreshed from the owner's state by the collision system.
struct Collider {
    ShapeKind kind;
    glm::dvec3 a_m;        // sphere/box centre, capsule start
    glm::dvec3 b_m;        // capsule end (unused otherwise)
    double radius_m;       // sphere, capsule
    glm::dvec3 half_extent_m; // box (axis-aligned in the hand's frame; hands do not rotate the cube)
};

struct Contact {
    ecs::Entity a;         // the Active side
    ecs::Entity b;
    glm::dvec3 point_m;
    glm::dvec3 normal;     // unit, from b towards a
    double depth_m;        // penetration, > 0
    std::int32_t pin;      // index of the kenzan pin when b is the kenzan, else -1
};

struct Contacts {
    std::vector<Contact> list;
    std::uint64_t pairs_tested;
};

// Counts the collider updates: a pass of detection spread over the ticks after one starts when this
// changes.
struct ColliderPass {
    std::uint64_t generation = 0;
};

} // namespace ikebana::components
