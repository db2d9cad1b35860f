#pragma once
// The mechanics of one spring stem (paper Eq. 1-3), used by spring_physics_system.
//
// Forces are exactly the paper's: structure springs along e_i (Eq. 1), and hinge springs whose
// restoring torque k_theta * dtheta_i becomes forces on P_{i-1} and P_{i+1} with the coupling force on
// P_i that cancels the translation (Eq. 2-3). Those are the gradient of the energy
// 1/2 k (|d|-l0)^2 + 1/2 k_theta (theta - theta0)^2, so energy and forces agree.
//
// Integration: linearised backward Euler (one Newton step per tick). A sunflower stem's axial springs
// have natural frequencies near 10^4 rad/s, far beyond what any explicit scheme survives at 1 kHz;
// backward Euler is unconditionally stable, dissipates rather than creates energy, and reaches
// exactly the static equilibrium of the exact forces (the cantilever test relies on that). The
// stiffness matrix is a positive semi-definite approximation (exact axial Hessian with the
// compressive part dropped, small-angle bending Hessian), which keeps the system matrix symmetric
// positive definite and banded (each point couples to +-2 neighbours): a banded L D L^T solve,
// O(n) per stem per tick.
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "components/stem.hpp"

namespace ikebana::systems::physics {

struct StemEnergy {
    double kinetic_j = 0.0;
    double elastic_j = 0.0;
    double gravitational_j = 0.0;
    [[nodiscard]] double total() const noexcept { return kinetic_j + elastic_j + gravitational_j; }
};


[[nodiscard]] StemEnergy stem_energy(const components::StemPoints& points, const components::StemRestShape& rest,
                                     const components::StemSprings& springs, const components::StemClamp* clamp,
                                     glm::dvec3 gravity, const components::StemFrame* frame = nullptr);

// The bend angle at interior point i (1..n-1), in radians.
[[nodiscard]] double hinge_angle(const components::StemPoints& points, std::size_t i);

struct StemSegment {
    glm::dvec3 direction{0.0}; // unit, P_{i-1} to P_i (zero for a collapsed segment)
    double length_m = 0.0;
};

// Spring, hinge, clamp, gravity and external forces on every point. `clamp` may be null; so may
// `frame` (then the rest bends take the plane the stem is bent in: see StemRestShape).
void stem_forces(const components::StemPoints& points, const components::StemRestShape& rest,
                 const components::StemSprings& springs, const components::StemClamp* clamp, glm::dvec3 gravity,
                 std::vector<glm::dvec3>& force_out, const components::StemFrame* frame = nullptr);
// The same with the segments' working memory given (an explicit integrator calling it every step).
void stem_forces(const components::StemPoints& points, const components::StemRestShape& rest,
                 const components::StemSprings& springs, const components::StemClamp* clamp, glm::dvec3 gravity,
                 std::vector<glm::dvec3>& force_out, std::vector<StemSegment>& segments,
                 const components::StemFrame* frame = nullptr);

// Working memory reused across steps so that the 1 kHz loop does not allocate.
struct StemSolverScratch {
    std::vector<double> band;             // the system matrix's lower band, padded (see stem_dynamics.cpp)
    std::vector<double> stiffness;        // H, kept for the end-of-step forces
    std::vector<double> rhs;              // padded; the new velocity once solved
    std::vector<double> motion;           // padded; the step's motion (for the end forces)
    std::vector<double> inverse_diagonal; // D^-1 of the L D L^T factors
    std::vector<double> segment_block;    // each segment's axial Hessian block, 6 values
    std::vector<double> bend_coupling;    // each point's hinge Hessian with itself, p-1, p-2
    std::vector<StemSegment> segments; // this step's
    std::vector<glm::dvec3> force;     // at the start of the step
    std::vector<glm::dvec3> end_force; // at its end, linearised (what a held point feels); see below
    // false: end_force is a copy of the start-of-step force (one banded product saved) for a step whose
    // end forces nobody feels: a tick's earlier parts, a stem no hand holds.
    bool want_end_force = true;
};

// How many equal steps one tick of dt is cut into, for every stem alike. The step is linearly implicit
// (one Newton step of backward Euler) and is stable at the paper's haptic period, 1 ms, for a stem of
// any stiffness and any number of segments (StemDynamics.*OneStepATick*: the cherry branch, fastest
// hinge mode omega dt = 55, and an 80-segment sunflower, 16 times the sunflower's 20-segment omega dt):
// the parts no longer grow with stiffness and segments (omega grows as segments squared), so a tick
// costs in proportion to a stem's points. A longer tick (a haptic rate set below the paper's) is cut
// into parts of at most max_part_s, max_substeps at most.
inline constexpr double max_part_s = 1e-3;
inline constexpr std::size_t max_substeps = 8;
[[nodiscard]] std::size_t tick_parts(double dt);

// A segment lying across something that holds it up (a container's rim): the height of the point on it,
// (1 - t) z_a + t z_b of its ends a = segment and b = segment + 1, is kept at least top_m by a stiff
// damped spring taken into the implicit solve, as a tree's floors are (stem_tree.hpp: TreeSupport). Put
// back by a position correction after the step instead, the two ends fought the segment's axial spring
// (1.2 MN/m for a chrysanthemum): a stem let go across a suiban's rim gained joules and tore out.
struct SegmentSupport {
    std::uint32_t segment; // its lower point's index
    double t;              // where along it the support is, 0 at its lower point
    double top_m;          // the lowest that point may be
};
inline constexpr double segment_support_n_per_m = 2.0e4;   // a 20 g flower on a rim sinks 10 um
inline constexpr double segment_support_n_s_per_m = 2.0;
// A stem found far below its support (carried through a wall by a hand) is raised over ticks, at most
// about this fast: the spring would fling it out in one (a branch laid 40 mm under a rim flew 25 cm).
inline constexpr double segment_support_exit_m_s = 0.1;

// Advances one stem by dt. Pinned points and a clamped P0 stay where they are. Returns false (and
// leaves the stem at rest where it was) if the step produced a non-finite value.
bool step_stem(components::StemPoints& points, const components::StemRestShape& rest,
               const components::StemSprings& springs, const components::StemClamp* clamp, glm::dvec3 gravity,
               double dt, StemSolverScratch& scratch, const components::StemFrame* frame = nullptr,
               std::span<const SegmentSupport> supports = {});

// One stem for step_stems: its parts, its own working memory, and its step (stems of different steps
// share the lanes: a stiff stem's first part is solved beside the others' whole tick).
struct StemStep {
    components::StemPoints* points;
    const components::StemRestShape* rest;
    const components::StemSprings* springs;
    const components::StemClamp* clamp; // may be null
    StemSolverScratch* scratch;
    double dt_s;
    const components::StemFrame* frame = nullptr; // the rest bends' directions (may be null)
    std::span<const SegmentSupport> supports{};   // what it lies across (a rim)
};

// The solves of four stems side by side (see step_stems), kept per group of four from call to call:
// a group of the same stems keeps its identity rows and padding.
struct LaneScratch {
    struct Group {
        std::vector<double> band;
        std::vector<double> rhs;
        std::vector<double> inverse_diagonal;
        std::size_t n = 0;
        std::array<std::size_t, 4> own{}; // each lane's unknowns
    };
    std::vector<Group> groups;
};

// Advances every stem by its dt_s, as step_stem does each (the same results bit for bit; ok[i] is 1
// where it would return true), their linear solves four at a time in the lanes of one register.
void step_stems(std::span<const StemStep> stems, glm::dvec3 gravity, LaneScratch& lane_scratch, std::span<std::uint8_t> ok);

// Room for a stem of up to `points` points, and (LaneScratch) for `stems` stems of that size solved four
// to a register: sized once when the scene loads, a new stem (a piece pruned off) allocates nothing.
void reserve_scratch(StemSolverScratch& scratch, std::size_t points);
void reserve_scratch(LaneScratch& scratch, const std::vector<std::size_t>& points_longest_first);

} // namespace ikebana::systems::physics
