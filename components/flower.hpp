#pragma once
// The paper's hierarchical flower (section 2.2): a flower entity owns part entities (petals, a stem,
// leaves; engine/ecs/hierarchy.hpp gives the ownership). Each part carries exactly one collision tag.
#include <cstdint>
#include <string>

#include <glm/glm.hpp>

namespace ikebana::components {

enum class PartKind : std::uint8_t { petal, stem, leaf };

struct Flower {
    std::string species;  // species id (assets/species/<id>.json)
    double total_mass_kg; // stem + head + leaves, for the holding moment (Eq. 7)
};

// One part of a flower. A part that is not the stem is attached to a stem point and follows it.
struct Part {
    PartKind kind;
    std::uint32_t stem_point;   // which mass point it hangs on
    glm::dvec3 offset_m;        // from that point, in the stem's local frame at rest
    std::string mesh;           // glTF file relative to assets/, or empty for a procedural shape
    float shade = 1.0f;         // its colour is the species' times this (petals that are not all alike)
    float cup_rad = 0.0f;       // how far it curls up from its base to its tip (a cupped petal; < 0 droops)
};

// Collision tags (paper 2.2, Mukai et al. 2009). Tags, not an enum field, so that an Inactive part is
// in no collision view at all: it costs nothing, however many there are.
//   Active   - moves and initiates contacts: hand cubes, the stem end that meets the pins
//   Passive  - is hit but never looks for contacts itself: kenzan pins, stem body, leaves, table
//   Inactive - never collides: petals (their contacts would change nothing the trainee feels)
// Pairs tested: Active x Active and Active x Passive. Passive x Passive is never tested: two passive
// things only meet through something active touching them, and skipping those pairs is the paper's
// whole speed-up. Inactive x anything is never tested.
struct ActiveCollider {};
struct PassiveCollider {};
struct InactiveCollider {};

} // namespace ikebana::components
