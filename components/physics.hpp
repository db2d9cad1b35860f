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

// A container on the table (a suiban, a vase; Passive), with the kenzan inside: its floor holds stems
// up, its wall keeps them in, or out, below the rim. Its water is drawn, not simulated.
struct Container {
    bool round;               // round: half_extent_m.x is the radius
    glm::dvec2 centre_m;
    glm::dvec2 half_extent_m; // of the inside
    double floor_z_m;         // the inside's floor
    double rim_z_m;
    double wall_m;            // thickness of the wall (and of the bottom, below floor_z_m)
    double water_z_m;
    // Where it stands (the table): a suiban's bottom is wall_m below its floor; a vase is filled up to
    // near its mouth (a kubari, or sand), so its floor is far above this.
    double base_z_m;

    // Whether a point seen from above is inside it, `margin_m` beyond its inside (half the wall: the
    // wall's middle). One definition for the physics, the drawing and the lesson's words.
    [[nodiscard]] bool holds_xy(glm::dvec2 xy, double margin_m = 0.0) const noexcept {
        const glm::dvec2 d = xy - centre_m;
        if (round) return d.x * d.x + d.y * d.y < (half_extent_m.x + margin_m) * (half_extent_m.x + margin_m);
        return (d.x < 0.0 ? -d.x : d.x) < half_extent_m.x + margin_m && (d.y < 0.0 ? -d.y : d.y) < half_extent_m.y + margin_m;
    }
};

} // namespace ikebana::components
