#pragma once
// A stem with side branches as one body. Each twig is a chain of its own (components::StemFork), but
// its bottom point and its parent's point `at_point` are one point of the system, and a root hinge
// joins the parent's segment below that point to the twig's first segment. The step is the chains'
// own (stem_dynamics.hpp: backward Euler, one Newton step) solved together: the system's graph is a
// tree (every point couples to its parent point and the parent's parent), and eliminated from the
// leaves up (children before parents) a tree's L D L^T has no fill, so the solve is O(points) with 3x3
// blocks, whatever the branching. A chain with no twigs takes stem_dynamics' banded path instead: the
// same system, the same answer (StemTree.OneChainStepsAsTheBandedSolverDoes), four stems to a register.
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "components/stem.hpp"
#include "systems/physics/stem_dynamics.hpp"

namespace ikebana::systems::physics {

struct TreeChain {
    components::StemPoints* points;
    const components::StemRestShape* rest;
    const components::StemSprings* springs;
    const components::StemClamp* clamp = nullptr; // the root chain's, if any
    const components::StemFrame* frame = nullptr;
    std::int32_t parent = -1;                     // an earlier chain's index; -1 for the root
    const components::StemFork* fork = nullptr;   // how it leaves its parent (parent >= 0)
};

// What a branch rests on (the table, a container's floor, the kenzan's plate) and leans on (a container's
// wall), taken into the solve: a point below its floor or in a wall is pushed out by a stiff damped
// spring solved with the step, and slides on a floor with Coulomb friction. A position correction after the step (table_support, for chains) would squeeze a
// stiff twig resting on its tip: the tip, a fraction of a gram, is put back each tick, the twig behind it
// is not, and the segment between them stays compressed by as much as the body sank.
struct TreeSupport {
    // The floor under (x, y) for a point of this radius; `end_drop_m` for a stem's bottom point (see
    // support_floor_m in table_support_system.hpp).
    double (*floor_m)(const void* context, glm::dvec2 xy, double radius_m, double end_drop_m) = nullptr;
    // How far a point must move to leave a wall (a container's), zero if it is in none.
    glm::dvec3 (*wall_push_m)(const void* context, glm::dvec3 x, double radius_m) = nullptr;
    // Where a chain of this radius crosses a wall below its rim: the segments that lie on the rim
    // (SegmentSupport; rim_supports in table_support_system.hpp). Their two points are held up there,
    // not pushed out of the wall one to each side.
    void (*rim_m)(const void* context, const std::vector<glm::dvec3>& x, double radius_m, std::vector<SegmentSupport>& out) = nullptr;
    const void* context = nullptr;
    double stiffness_n_per_m = 2.0e4; // a 20 g branch on two points sinks 5 um; two hands pressing 20 N, 1 mm
    double damping_n_s_per_m = 2.0;
    double exit_speed_m_s = 0.1;      // the fastest a point leaves its floor
    double friction = 0.6;
    double gravity_m_s2 = 9.80665;
};

// Working memory kept from tick to tick: the 1 kHz loop does not allocate once sizes settle.
struct TreeScratch {
    std::vector<std::vector<std::uint32_t>> node_of; // per chain, per point
    std::vector<std::int32_t> parent_node;
    // Blocks as plain numbers, written entry by entry (glm's 3x3 temporaries for a scalar on the diagonal
    // were half the tree's step): a point's diagonal block and its inverse are symmetric (xx xy xz yy yz
    // zz); its coupling with its parent (rows: its axes, columns: the parent's) is not once eliminated
    // (row-major).
    std::vector<std::array<double, 6>> diagonal, inverse;
    std::vector<std::array<double, 9>> to_parent;
    // A point's coupling with its parent's parent is a hinge's alone, the same on every axis (k c0 c2 I),
    // and elimination never changes it: one number a point.
    std::vector<double> to_grandparent;
    std::vector<std::int64_t> topology; // the chains' sizes, parents and forks the numbering was made for
    std::vector<std::uint8_t> hinge_known;
    std::vector<glm::dvec3> rhs, fixed_velocity, node_force;
    std::vector<std::uint8_t> fixed;
    std::vector<glm::dvec3> held_position; // held points' positions while the end forces are taken a step on
    std::vector<std::uint8_t> resting; // on its floor this step
    std::vector<glm::dvec3> wall_normal; // out of the wall it is in this step (zero: none)
    std::vector<std::uint8_t> on_rim;     // lying on a rim this step (not pushed out of its wall)
    std::vector<SegmentSupport> rim;      // one chain's rim crossings, while they are taken in
    std::vector<std::vector<glm::dvec3>> force;        // per chain, at the step's start
    std::vector<std::vector<StemSegment>> segments;    // per chain
    std::vector<std::vector<glm::dvec3>> load;         // per chain: the body's own force on each point (see step_tree)
    // Per twig: how its root hinge's energy changes as its parent's frame turns at the fork (dE/dphi,
    // d2E/dphi2): the parent's frame takes them into its twist (StemFrame::external_twist_*).
    std::vector<double> frame_gradient_nm, frame_stiffness_nm;
};

// The root hinge's rest bend as a rotation vector in the room (the fork's angle about its direction in
// the parent's frame at the parent's segment `at_point - 1`, carried to where that segment points now).
[[nodiscard]] glm::dvec3 fork_rest_bend(const TreeChain& twig, const TreeChain& parent, glm::dvec3 e_in);


// One step of dt for the whole tree; false (and nothing moved) for a non-finite or indefinite system.
// Afterwards scratch.load[c][j] is the body's own force on chain c's point j (springs, hinges, clamp,
// gravity, without what other systems pushed): at the step's end if `end_forces`, else at its start.
// A shared point's load is the whole body's there (the parent's point and its twigs' P0 alike).
// External forces are not cleared (the caller does, as for a chain).
// `support`: what it rests on (none: nothing).
// Room for a tree of up to `chains` chains, `nodes` points in all and `points` a chain, sized once when
// the scene loads: a branch pruned off (a tree of its own) allocates nothing.
void reserve_scratch(TreeScratch& scratch, std::size_t chains, std::size_t nodes, std::size_t points);

bool step_tree(std::span<const TreeChain> chains, glm::dvec3 gravity, double dt, TreeScratch& scratch, bool end_forces,
               const TreeSupport* support = nullptr);

// The tree's energy: its chains' and its root hinges' (a twig's P0 is a mass of its own at its parent's point).
[[nodiscard]] StemEnergy tree_energy(std::span<const TreeChain> chains, glm::dvec3 gravity);

} // namespace ikebana::systems::physics
