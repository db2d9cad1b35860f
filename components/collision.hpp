#pragma once
// Collision shapes and the contacts the collision system reports each pass.
#include <cstdint>
#include <utility>
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

// A collision pass in progress (one entity has it; the pass makes it on first use). Spread over the
// haptic ticks, a pass keeps what it took at its start and what it found so far from tick to tick, so
// that is state of the world: kept here, in the registry, it enters the state hash and is restored with
// the world, never left behind in a system object.
struct CollisionPass {
    double cell_size_m = 0.03;
    std::int64_t step = -1;               // spread pass: -1 waiting for an update; 0 index; then gathers, slices, pins
    std::uint64_t seen_generation = 0;    // the collider update this pass started from
    std::vector<std::pair<std::int64_t, std::uint32_t>> cells; // (cell, Active collider), sorted
    std::vector<std::uint64_t> pairs;     // (Active i) << 32 | j, to be tested
    std::vector<ecs::Entity> entities;
    std::vector<Collider> colliders;      // as they were at the start: the pass is one instant's
    std::vector<ecs::Entity> owners;
    std::vector<std::uint8_t> active;
    std::uint64_t active_count = 0;
    std::vector<Contact> found;           // this pass's, until published
    std::uint64_t pairs_tested = 0;
};

// Counts the collider updates: a pass of detection spread over the ticks after one starts when this
// changes.
struct ColliderPass {
    std::uint64_t generation = 0;
};

} // namespace ikebana::components
