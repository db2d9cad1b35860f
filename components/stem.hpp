#pragma once
// The spring stem of Figure 4: mass points P0..Pn joined by structure springs S1..Sn (Eq. 1) and hinge
// springs H1..Hn-1 (Eq. 2-3). P0 is the bottom (the end that goes into the kenzan). SI units.
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

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
};

} // namespace ikebana::components
