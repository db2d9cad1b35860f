#pragma once
// Narrow-phase tests between the collider shapes. Each returns a contact (normal from b towards a,
// penetration depth > 0) or nothing.
#include <optional>

#include <glm/glm.hpp>

#include "components/collision.hpp"
#include "components/kenzan.hpp"

namespace ikebana::systems::collision {

struct Hit {
    glm::dvec3 point_m;
    glm::dvec3 normal; // unit, from b towards a
    double depth_m;
};

// Closest points of segments [p0,p1] and [q0,q1]: parameters s, t in [0, 1].
void closest_segment_points(glm::dvec3 p0, glm::dvec3 p1, glm::dvec3 q0, glm::dvec3 q1, double& s, double& t);

std::optional<Hit> collide(const components::Collider& a, const components::Collider& b);

// A capsule against one kenzan pin: a vertical trunk of radius r ending in a cone of tip_length.
std::optional<Hit> collide_capsule_pin(const components::Collider& capsule, glm::dvec3 pin_base,
                                       const components::PinShape& pin);

// Axis-aligned bounds of a collider.
struct Bounds {
    glm::dvec3 lo;
    glm::dvec3 hi;
};
Bounds bounds_of(const components::Collider& c);

} // namespace ikebana::systems::collision
