#pragma once
// A stem with side branches as one body. Each twig is a chain of its own (components::StemFork), but
// its bottom point and its parent's point `at_point` are one point of the system, and a root hinge
// joins the parent's segment below that point to the twig's first segment. The step is the chains'
// own (stem_dynamics.hpp: backward Euler, one Newton step) solved together: the system's graph is a
// tree (every point couples to its parent point and the parent's parent), and eliminated from the
// leaves up (children before parents) a tree's L D L^T has no fill, so the solve is O(points) with 3x3
// blocks, whatever the branching. A chain with no twigs takes stem_dynamics' banded path instead: the
// same system, the same answer (StemTree.OneChainStepsAsTheBandedSolverDoes), four stems to a register.
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

// Working memory kept from tick to tick: the 1 kHz loop does not allocate once sizes settle.
struct TreeScratch {
    std::vector<std::vector<std::uint32_t>> node_of; // per chain, per point
    std::vector<std::int32_t> parent_node;
    std::vector<glm::dmat3> diagonal, to_parent, to_grandparent, inverse;
    std::vector<glm::dvec3> rhs, fixed_velocity, node_force;
    std::vector<std::uint8_t> fixed;
    std::vector<std::vector<glm::dvec3>> force;        // per chain, at the step's start
    std::vector<std::vector<StemSegment>> segments;    // per chain
    std::vector<std::vector<glm::dvec3>> load;         // per chain: the body's own force on each point (see step_tree)
};

// The root hinge's rest bend as a rotation vector in the room (the fork's angle about its direction in
// the parent's frame at the parent's segment `at_point - 1`, carried to where that segment points now).
[[nodiscard]] glm::dvec3 fork_rest_bend(const TreeChain& twig, const TreeChain& parent, glm::dvec3 e_in);

// How many equal steps one tick must be cut into (stable_substeps over the chains and root hinges).
[[nodiscard]] std::size_t tree_substeps(std::span<const TreeChain> chains, double dt);

// One step of dt for the whole tree; false (and nothing moved) for a non-finite or indefinite system.
// Afterwards scratch.load[c][j] is the body's own force on chain c's point j (springs, hinges, clamp,
// gravity, without what other systems pushed): at the step's end if `end_forces`, else at its start.
// A shared point's load is the whole body's there (the parent's point and its twigs' P0 alike).
// External forces are not cleared (the caller does, as for a chain).
bool step_tree(std::span<const TreeChain> chains, glm::dvec3 gravity, double dt, TreeScratch& scratch, bool end_forces);

// The tree's energy: its chains' and its root hinges' (a twig's P0 is a mass of its own at its parent's point).
[[nodiscard]] StemEnergy tree_energy(std::span<const TreeChain> chains, glm::dvec3 gravity);

} // namespace ikebana::systems::physics
