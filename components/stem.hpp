#pragma once
// The spring stem of Figure 4: mass points P0..Pn joined by structure springs S1..Sn (Eq. 1) and hinge
// springs H1..Hn-1 (Eq. 2-3). P0 is the bottom (the end that goes into the kenzan). SI units.
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "engine/ecs/entity.hpp"

namespace ikebana::components {

struct StemPoints {
    std::vector<glm::dvec3> position_m;
    std::vector<glm::dvec3> velocity_m_s;
    std::vector<double> mass_kg;
    std::vector<glm::dvec3> external_force_n; // from hands, contacts and pins; cleared after each step
    std::vector<std::uint8_t> pinned;         // 1: held in place (a hand's grip, a test clamp)
};

// The natural shape: segment lengths l_i and hinge angles theta0_i. A curved rest shape (a branch's
// natural bend) has theta0 != 0.
struct StemRestShape {
    std::vector<double> segment_length_m; // l_1..l_n
    std::vector<double> hinge_angle_rad;  // theta0 at P1..Pn-1
    double diameter_m;
    // Which way each rest bend turns about the stem, as a unit vector (cos psi, sin psi) in the material
    // frame of the segment below the hinge (StemFrame: d1, d2 = e x d1): the rest bend is the rotation
    // theta0 (cos psi d1 + sin psi d2) from that segment to the next. A bend with a direction of its own
    // (a permanent set made with both hands) stays on its side of the stem however the stem is carried or
    // turned. A zero vector, or none at all (empty), is a bend without a direction: it takes the plane
    // the hinge is bent in now, so it settles wherever the stem's weight takes it (a species' natural
    // curve, for now; see docs/physics.md).
    std::vector<glm::dvec2> hinge_bend_direction;
};

// The stem's material frame (Bergou et al. 2008, "Discrete elastic rods"): per segment a unit director
// d1 across it (d2 = e x d1), the bark's orientation. Twist is quasi-static (a stem's torsional waves
// are far faster than a tick): each tick the directors are carried along with their segments'
// motion (parallel transport in time), then turned about their segments to the least energy of twist
// (G J) and of the rest bends' directions, with the segments a grip or the kenzan holds kept as held.
struct StemFrame {
    std::vector<glm::dvec3> director;          // d1 per segment, unit, across the segment
    std::vector<glm::dvec3> segment_direction; // each segment's direction when the directors were last carried
    // Written by whatever holds the stem this tick (a hand's grip, the kenzan), consumed by the frame's
    // update: held segments' directors are set to these.
    std::vector<std::uint8_t> held;
    std::vector<glm::dvec3> held_director;
    std::vector<double> external_twist_nm; // a twisting moment about each segment (tests, a turning tool)
    // And a stiffness against turning each segment (N m / rad): what a twig's fork puts on the segment it
    // leaves (its side is in this frame). Consumed with the moments; empty: none.
    std::vector<double> external_twist_stiffness_nm;
    double twist_stiffness_nm2 = 0.0;      // G J
    // The last update found nothing holding or twisting the frame, and relaxed its twist (with directed
    // bends: its step turned nothing): until something does, the update carries the directors (and
    // solves a frame with directed bends again) every quiet_carry_ticks-th tick only (update_frame).
    bool relaxed = false;
    // What each segment was last held at: a hold that has not changed (the kenzan's, most ticks) does not
    // wake a relaxed frame. And how many ticks a quiet frame has gone uncarried (see update_frame).
    std::vector<glm::dvec3> held_at;
    std::uint8_t quiet_ticks = 0;
};

struct StemSprings {
    // Structure springs: k = E A / l_i per segment (Eq. 1 uses one k; the axial and the bending
    // constants differ in unit and size, so each spring family has its own).
    std::vector<double> axial_n_per_m;
    // Hinge springs: k_theta = E I / l at P1..Pn-1 (N m / rad), from the species' E and I.
    std::vector<double> hinge_nm_per_rad;
    double stiffness_damping_s;   // Rayleigh beta: damps relative motion only, keeps momentum
    double air_drag_per_s;        // Rayleigh alpha: damps absolute motion (0 in momentum tests)
};

// The stem's own force on every point in this tick's physics step (springs, hinges, clamp, gravity; not
// what other systems pushed): computed once by the physics, read by whatever else needs it (what a hand
// holding the stem feels). While a point is pinned (held) these are the forces at the step's end, as
// the implicit step has them; for a stem nobody holds, the forces at its start (the end forces cost a
// banded product a stem and nothing reads them).
struct StemLoads {
    std::vector<glm::dvec3> force_n;
};

// A clamp of the stem bottom: the bottom point held and the first segment held along a direction by a
// root hinge of stiffness 2 E I / l_1 (a fully built-in end; the factor 2 is the half segment between
// the clamp and P1, the trapezoid rule that makes the chain match Euler-Bernoulli).
struct StemClamp {
    bool engaged;
    glm::dvec3 anchor_m;
    glm::dvec3 direction;  // unit, from P0 towards P1
    double hinge_nm_per_rad;
    // The bottom segment's director (StemFrame) as the clamp took it: the pins hold the stem's turn
    // about its axis as well as its place. Zero: the clamp does not hold the frame.
    glm::dvec3 director{0.0};
};

// A side branch (a twig): a stem of its own whose bottom point P0 is its parent's point `at_point`, the
// two solved as one body (stem_tree.hpp: P0 and the parent's point are one point of the system, and a
// root hinge between the parent's segment below that point and the twig's first segment keeps the fork's
// angle). The fork's rest bend is `angle_rad` about the direction (cos psi, sin psi) in the parent's
// material frame there (StemFrame), so a branch turned about its axis turns its twigs with it.
struct StemFork {
    ecs::Entity parent;      // a stem, or another twig
    std::uint32_t at_point;  // 1..n of the parent's points (the root hinge needs the segment below it)
    double angle_rad;        // between the parent's segment and the twig's first, at rest
    glm::dvec2 direction;    // which way about the parent the twig leaves, in the parent's frame
    double hinge_nm_per_rad; // the root hinge's stiffness: the twig's own E I over its first segment
};

// On a stem with side branches: every twig and twig of a twig, parents before their children.
struct Twigs {
    std::vector<ecs::Entity> entities;
};

} // namespace ikebana::components
