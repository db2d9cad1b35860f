#pragma once
// Builds the spring-stem components from material data: a designer gives E, the diameter and the
// masses; the spring constants follow (axial k = E A / l, hinge k_theta = E I / l).
#include <cstdint>

#include <glm/glm.hpp>

#include "components/stem.hpp"

namespace ikebana::systems::physics {

struct StemSpec {
    std::uint32_t segments = 20;
    double length_m = 0.23;
    double diameter_m = 0.0075;
    double youngs_modulus_pa = 5.0e7;
    // Twisting: G = E / (2 (1 + nu)) unless a shear modulus is given (> 0); J = 2 I (a round section's
    // polar moment), so G J = E I / (1 + nu). Wood and green stems: nu about 0.3-0.4.
    double poisson_ratio = 0.3;
    double shear_modulus_pa = 0.0;
    double second_moment_m4 = 0.0; // 0: solid circular section, pi d^4 / 64
    double stem_mass_kg = 0.005;
    double head_mass_kg = 0.0;     // carried by the top point (a sunflower's head)
    // The natural bend: total angle from bottom to top, spread evenly over the hinges, in the plane
    // spanned by `direction` and `bend_towards`.
    double rest_bend_rad = 0.0;
    glm::dvec3 bend_towards{1.0, 0.0, 0.0};
    glm::dvec3 base_m{0.0};
    glm::dvec3 direction{0.0, 0.0, 1.0};
    // Plant tissue damps its first sway mode to roughly 5-10 % of critical; these give that range
    // for the shipped species (zeta = beta w / 2 + alpha / 2w).
    double stiffness_damping_s = 0.004;
    double air_drag_per_s = 1.0;
};

struct BuiltStem {
    components::StemPoints points;
    components::StemRestShape rest;
    components::StemSprings springs;
    components::StemFrame frame;  // without twist along the laid stem; its rest bends' directions in it
    double bending_stiffness_nm2; // E I
    double twist_stiffness_nm2;   // G J
};

[[nodiscard]] double second_moment_of_area(double diameter_m);
[[nodiscard]] BuiltStem build_stem(const StemSpec& spec);
// A side branch leaving `parent` at its point `at_point` (1..n): `spec` without its base and direction,
// which the fork gives (the parent's point; the parent's segment below it turned by `angle_rad` about
// `direction` in the parent's frame there). Its natural curve (spec.rest_bend_rad) turns up, toward the
// light, or down if negative (a weeping twig). The root hinge: 2 E I / l_1 of the twig, as the kenzan's clamp (a built-in end).
struct BuiltTwig {
    BuiltStem stem;
    components::StemFork fork;
};
// `curve_towards`: where its natural curve turns instead (a branch laid on a table curves its twigs along
// the table); zero: up, or down.
[[nodiscard]] BuiltTwig build_twig(StemSpec spec, const components::StemPoints& parent, const components::StemFrame& parent_frame,
                                   std::uint32_t at_point, double angle_rad, glm::dvec2 direction, glm::dvec3 curve_towards = glm::dvec3{0.0});
// A built-in (cantilever) clamp of the stem's bottom in its current pose.
[[nodiscard]] components::StemClamp clamp_bottom(const BuiltStem& stem);

} // namespace ikebana::systems::physics
