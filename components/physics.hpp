#pragma once
// World-wide physics settings and what the physics reports back (registry resources).
#include <glm/glm.hpp>

namespace ikebana::components {

struct PhysicsSettings {
    glm::dvec3 gravity_m_s2{0.0, 0.0, -9.80665};
};

// Energy of everything the spring system integrates, for summaries and the no-explosion checks.
struct WorldEnergy {
    double kinetic_j;
    double elastic_j;
    double gravitational_j; // relative to z = 0
    [[nodiscard]] double total() const noexcept { return kinetic_j + elastic_j + gravitational_j; }
};

} // namespace ikebana::components

namespace ikebana::components {

// The table top everything stands on (Passive). Flowers lying on it are held up with friction.
struct Table {
    double height_m;
    double friction; // Coulomb coefficient for points resting on it
};

} // namespace ikebana::components
