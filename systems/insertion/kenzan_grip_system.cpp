#include "systems/insertion/kenzan_grip_system.hpp"

#include <algorithm>
#include <cmath>

#include "engine/ecs/registry.hpp"

namespace ikebana::systems {

using namespace components;

namespace {
double angle_between(glm::dvec3 a, glm::dvec3 b) {
    return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
}

double stem_length(const std::vector<glm::dvec3>& x) {
    double length = 0.0;
    for (std::size_t i = 1; i < x.size(); ++i) length += glm::length(x[i] - x[i - 1]);
    return length;
}

// Rotates `from` towards `to` so that the angle between them becomes `angle` (<= current).
glm::dvec3 rotate_towards(glm::dvec3 from, glm::dvec3 to, double angle) {
    const glm::dvec3 axis = glm::cross(to, from);
    const double s = glm::length(axis);
    if (s < 1e-12) return to;
    const glm::dvec3 k = axis / s;
    // Rodrigues: `to` rotated about k by `angle` lands between to and from.
    return glm::normalize(to * std::cos(angle) + glm::cross(k, to) * std::sin(angle) + k * glm::dot(k, to) * (1.0 - std::cos(angle)));
}
} // namespace

void KenzanGripSystem::operator()(sched::SystemContext& ctx) {
    auto& r = ctx.registry;
    r.view<KenzanGrip, StemClamp, const PinEngagement, const StemPoints, const StemSprings>().each(
        [&](ecs::Entity e, KenzanGrip& grip, StemClamp& clamp, const PinEngagement& engagement, const StemPoints& points,
            const StemSprings& springs) {
            const auto* grasp = r.try_get<const Grasp>(e);
            const bool held = grasp && grasp->hands > 0;
            const auto& x = points.position_m;
            if (held || !engagement.in_kenzan || x.size() < 2) {
                grip.engaged = false;
                clamp.engaged = false;
                return;
            }
            const glm::dvec3 first = glm::normalize(x[1] - x[0]);
            const double root_stiffness = 2.0 * (springs.hinge_nm_per_rad.empty() ? 0.0 : springs.hinge_nm_per_rad[0]);
            if (!grip.engaged) {
                grip.engaged = true;
                grip.fallen = false;
                grip.fall_reason = FallReason::none;
                grip.yielded = false;
                grip.entry_axis = first;
                grip.entry_line = glm::normalize(x.back() - x[0]);
                grip.release_height_m = x.back().z - x[0].z;
                clamp = StemClamp{true, x[0], first, root_stiffness};
                if (const auto* frame = r.try_get<const StemFrame>(e); frame && !frame->director.empty()) clamp.director = frame->director.front();
            }
            // The pins hold the bottom's turn about the stem where it went in.
            if (auto* frame = r.try_get<StemFrame>(e); frame && !frame->held.empty() && glm::dot(clamp.director, clamp.director) > 0.5) {
                frame->held.front() = 1;
                frame->held_director.front() = clamp.director;
            }
            grip.holding_moment_nm = engagement.holding_moment_nm;
            // Elastic up to the holding moment, then the hinge yields (return mapping).
            if (root_stiffness > 0.0) {
                const double limit = grip.holding_moment_nm / root_stiffness;
                if (angle_between(clamp.direction, first) > limit) {
                    clamp.direction = rotate_towards(clamp.direction, first, limit);
                    if (!grip.yielded && !grip.fallen) {
                        grip.yielded = true;
                        grip.yield_holding_nm = engagement.holding_moment_nm;
                        grip.yield_gravity_nm = engagement.gravity_moment_nm;
                    }
                }
            }
            if (!grip.fallen) {
                const glm::dvec3 axis = glm::normalize(x.back() - x[0]);
                const double height = x.back().z - x[0].z;
                if (angle_between(axis, glm::dvec3{0.0, 0.0, 1.0}) >= lying_angle_rad) grip.fall_reason = FallReason::lies_flat;
                else if (angle_between(grip.entry_axis, clamp.direction) > fall_angle_rad ||
                         (grip.yielded && angle_between(grip.entry_line, axis) > fall_angle_rad))
                    grip.fall_reason = FallReason::tipped;
                else if (height < dropped_fraction * stem_length(x)) grip.fall_reason = FallReason::dropped;
                if (grip.fall_reason != FallReason::none) {
                    grip.fallen = true;
                    grip.fell_at_us = ctx.time_us;
                }
            }
        });
}

} // namespace ikebana::systems
