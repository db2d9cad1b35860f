#include "systems/physics/stem_builder.hpp"

#include "systems/physics/part_attachment.hpp"
#include "systems/physics/stem_frame.hpp"

#include <cmath>

#include <glm/gtc/constants.hpp>

namespace ikebana::systems::physics {

double second_moment_of_area(double diameter_m) {
    return glm::pi<double>() * std::pow(diameter_m, 4) / 64.0;
}

BuiltStem build_stem(const StemSpec& spec) {
    const std::uint32_t n = spec.segments;
    const double l = spec.length_m / n;
    const double area = glm::pi<double>() * spec.diameter_m * spec.diameter_m / 4.0;
    const double inertia = spec.second_moment_m4 > 0.0 ? spec.second_moment_m4 : second_moment_of_area(spec.diameter_m);
    const double ei = spec.youngs_modulus_pa * inertia;

    BuiltStem stem;
    stem.bending_stiffness_nm2 = ei;
    stem.rest.diameter_m = spec.diameter_m;
    stem.rest.segment_length_m.assign(n, l);
    const double per_hinge = n > 1 ? spec.rest_bend_rad / (n - 1) : 0.0;
    stem.rest.hinge_angle_rad.assign(n > 0 ? n - 1 : 0, std::abs(per_hinge));
    stem.springs.axial_n_per_m.assign(n, spec.youngs_modulus_pa * area / l);
    stem.springs.hinge_nm_per_rad.assign(n > 0 ? n - 1 : 0, ei / l);
    stem.springs.stiffness_damping_s = spec.stiffness_damping_s;
    stem.springs.air_drag_per_s = spec.air_drag_per_s;

    // Lay the points along the rest shape: a circular arc when bent, a line otherwise.
    const glm::dvec3 dir = glm::normalize(spec.direction);
    glm::dvec3 side = spec.bend_towards - glm::dot(spec.bend_towards, dir) * dir;
    // A curve toward the stem's own direction has no side: it takes the room's x across the stem (the
    // bark's first director), so a curved stem is always laid curved, with its curve's direction.
    side = glm::length(side) > 1e-12 ? glm::normalize(side) : (spec.rest_bend_rad != 0.0 ? first_director(dir) : glm::dvec3{0.0});
    auto& pts = stem.points;
    pts.position_m.resize(n + 1);
    pts.position_m[0] = spec.base_m;
    double heading = 0.0; // angle of the current segment from `dir`, towards `side`
    for (std::uint32_t i = 1; i <= n; ++i) {
        if (i > 1) heading += per_hinge;
        const glm::dvec3 e = std::cos(heading) * dir + std::sin(heading) * side;
        pts.position_m[i] = pts.position_m[i - 1] + l * e;
    }
    pts.velocity_m_s.assign(n + 1, glm::dvec3{0.0});
    pts.external_force_n.assign(n + 1, glm::dvec3{0.0});
    pts.pinned.assign(n + 1, 0);
    // Lumped masses: each point carries half of each segment beside it.
    pts.mass_kg.assign(n + 1, 0.0);
    const double segment_mass = spec.stem_mass_kg / n;
    for (std::uint32_t i = 1; i <= n; ++i) {
        pts.mass_kg[i - 1] += 0.5 * segment_mass;
        pts.mass_kg[i] += 0.5 * segment_mass;
    }
    pts.mass_kg[n] += spec.head_mass_kg;
    // The frame: its first director the room's x across the first segment (as parts were placed before
    // the frame), carried up without twist.
    // The natural curve's bends get their direction in that frame: the curve is the wood's, on its side
    // of the bark wherever the branch is turned (without one it rolled down under its weight).
    const double shear = spec.shear_modulus_pa > 0.0 ? spec.shear_modulus_pa : spec.youngs_modulus_pa / (2.0 * (1.0 + spec.poisson_ratio));
    stem.twist_stiffness_nm2 = shear * 2.0 * inertia;
    stem.frame = frame_along(pts.position_m, first_director(pts.position_m[1] - pts.position_m[0]), stem.twist_stiffness_nm2);
    if (spec.rest_bend_rad != 0.0 && glm::length(side) > 0.0) rest_bends_from_shape(pts.position_m, stem.frame, stem.rest);
    else stem.rest.hinge_bend_direction.assign(stem.rest.hinge_angle_rad.size(), glm::dvec2{0.0});
    return stem;
}

BuiltTwig build_twig(StemSpec spec, const components::StemPoints& parent, const components::StemFrame& parent_frame,
                     std::uint32_t at_point, double angle_rad, glm::dvec2 direction, glm::dvec3 curve_towards) {
    const auto& x = parent.position_m;
    const glm::dvec3 e_in = glm::normalize(x[at_point] - x[at_point - 1]);
    const std::uint32_t segment = at_point - 1;
    glm::dvec3 d1 = segment < parent_frame.director.size() ? parent_frame.director[segment] : first_director(e_in);
    d1 = glm::normalize(d1 - glm::dot(d1, e_in) * e_in);
    const glm::dvec2 dir = glm::length(direction) > 0.0 ? glm::normalize(direction) : glm::dvec2{1.0, 0.0};
    const glm::dvec3 axis = dir.x * d1 + dir.y * glm::cross(e_in, d1); // the fork's rotation, across the parent
    spec.base_m = x[at_point];
    spec.direction = std::cos(angle_rad) * e_in + std::sin(angle_rad) * glm::cross(axis, e_in);
    // A natural curve turns up toward the light; a negative one down (a weeping twig).
    spec.bend_towards = glm::dot(curve_towards, curve_towards) > 0.0 ? curve_towards : glm::dvec3{0.0, 0.0, spec.rest_bend_rad < 0.0 ? -1.0 : 1.0};
    spec.rest_bend_rad = std::abs(spec.rest_bend_rad);
    BuiltTwig twig{build_stem(spec), {}};
    twig.fork.at_point = at_point;
    twig.fork.angle_rad = angle_rad;
    twig.fork.direction = dir;
    twig.fork.hinge_nm_per_rad = 2.0 * twig.stem.bending_stiffness_nm2 / twig.stem.rest.segment_length_m[0];
    return twig;
}

components::StemClamp clamp_bottom(const BuiltStem& stem) {
    const auto& x = stem.points.position_m;
    components::StemClamp clamp{};
    clamp.engaged = true;
    clamp.anchor_m = x[0];
    clamp.direction = glm::normalize(x[1] - x[0]);
    clamp.hinge_nm_per_rad = 2.0 * stem.bending_stiffness_nm2 / stem.rest.segment_length_m[0];
    return clamp;
}

} // namespace ikebana::systems::physics
