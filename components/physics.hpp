#pragma once
// World-wide physics settings and what the physics reports back (registry resources).
#include <cstddef>
#include <vector>

#include <glm/glm.hpp>

namespace ikebana::components {

struct PhysicsSettings {
    glm::dvec3 gravity_m_s2{0.0, 0.0, -9.80665};
};

// How many bodies the physics may solve at once over the scene's life, and how large: what is there when
// it loads and every loose piece a cut or pruning can make of it (systems/insertion/structure_reserve).
// The 1 kHz lane's systems size their working memory to it once, so that a piece that comes off
// allocates nothing there (glibc's allocator locks do not inherit priority).
struct BodyCapacity {
    std::size_t bodies = 0;       // stems and trees at once, every loose piece included
    std::size_t trees = 0;        // of them, stems with twigs (a branch pruned with its own twigs is one)
    std::vector<std::size_t> stem_points; // every body that can be a stem without twigs, its points, longest first
    std::size_t points = 0;       // the most points one stem or twig has
    std::size_t tree_chains = 0;  // the most chains (a stem and its twigs) one tree has
    std::size_t tree_nodes = 0;   // the most points one tree has
    std::size_t cuttings = 0;     // loose pieces that can lie on the table at once
    std::size_t stalks = 0;       // of them, leaves and blossoms stripped onto a stalk
    std::size_t stalk_points = 0; // a stalk's points
    std::size_t pieces = 0;       // every twig and stalk: the pieces all cuttings together can draw
    std::size_t parts = 0;        // drawn parts (leaves, blossoms) on all of them
    std::size_t piece_parts = 0;  // the most drawn parts one stem or twig carries
    std::size_t mesh_name = 0;    // the longest part's mesh name
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
