#include "systems/collision/narrow_phase.hpp"

#include <algorithm>
#include <cmath>

namespace ikebana::systems::collision {

using components::Collider;
using components::ShapeKind;

namespace {

constexpr double tiny = 1e-12;

glm::dvec3 any_perpendicular(glm::dvec3 v) {
    return std::abs(v.x) < 0.9 ? glm::normalize(glm::cross(v, glm::dvec3{1, 0, 0})) : glm::normalize(glm::cross(v, glm::dvec3{0, 1, 0}));
}

// Two spheres (centres ca, cb) touching: the shared core of sphere, capsule and pin tests.
std::optional<Hit> spheres(glm::dvec3 ca, double ra, glm::dvec3 cb, double rb, glm::dvec3 fallback_normal) {
    const glm::dvec3 d = ca - cb;
    const double dist = glm::length(d);
    const double depth = ra + rb - dist;
    if (depth <= 0.0) return std::nullopt;
    const glm::dvec3 n = dist > tiny ? d / dist : fallback_normal;
    return Hit{cb + n * (rb - 0.5 * depth), n, depth};
}

glm::dvec3 closest_on_box(glm::dvec3 centre, glm::dvec3 half, glm::dvec3 p) {
    return glm::clamp(p, centre - half, centre + half);
}

// A point (with radius) against a box: handles the point being inside the box.
std::optional<Hit> point_box(glm::dvec3 p, double r, glm::dvec3 centre, glm::dvec3 half, bool box_is_a) {
    const glm::dvec3 q = closest_on_box(centre, half, p);
    const glm::dvec3 d = p - q;
    const double dist = glm::length(d);
    Hit hit{};
    if (dist > tiny) {
        if (dist >= r) return std::nullopt;
        hit = Hit{q, d / dist, r - dist};
    } else {
        // Inside: push out through the nearest face.
        const glm::dvec3 local = p - centre;
        const glm::dvec3 gap = half - glm::abs(local);
        int axis = 0;
        if (gap.y < gap[axis]) axis = 1;
        if (gap.z < gap[axis]) axis = 2;
        glm::dvec3 n{0.0};
        n[axis] = local[axis] >= 0.0 ? 1.0 : -1.0;
        hit = Hit{p, n, gap[axis] + r};
    }
    if (box_is_a) hit.normal = -hit.normal;
    return hit;
}

// Distance from a point on the segment to the box is convex in the segment parameter: a ternary
// search finds the closest one.
double closest_segment_parameter_to_box(glm::dvec3 a, glm::dvec3 b, glm::dvec3 centre, glm::dvec3 half) {
    double lo = 0.0;
    double hi = 1.0;
    auto dist2 = [&](double t) {
        const glm::dvec3 p = a + t * (b - a);
        const glm::dvec3 d = p - closest_on_box(centre, half, p);
        // Inside the box: rank deeper points first so the push-out uses the most-penetrating point.
        if (glm::dot(d, d) == 0.0) return -glm::length(glm::min(half - glm::abs(p - centre), glm::dvec3{1e9}));
        return glm::dot(d, d);
    };
    for (int i = 0; i < 40; ++i) {
        const double m1 = lo + (hi - lo) / 3.0;
        const double m2 = hi - (hi - lo) / 3.0;
        if (dist2(m1) <= dist2(m2)) hi = m2;
        else lo = m1;
    }
    return 0.5 * (lo + hi);
}

} // namespace

void closest_segment_points(glm::dvec3 p0, glm::dvec3 p1, glm::dvec3 q0, glm::dvec3 q1, double& s, double& t) {
    const glm::dvec3 d1 = p1 - p0;
    const glm::dvec3 d2 = q1 - q0;
    const glm::dvec3 r = p0 - q0;
    const double a = glm::dot(d1, d1);
    const double e = glm::dot(d2, d2);
    const double f = glm::dot(d2, r);
    if (a <= tiny && e <= tiny) {
        s = t = 0.0;
        return;
    }
    if (a <= tiny) {
        s = 0.0;
        t = std::clamp(f / e, 0.0, 1.0);
        return;
    }
    const double c = glm::dot(d1, r);
    if (e <= tiny) {
        t = 0.0;
        s = std::clamp(-c / a, 0.0, 1.0);
        return;
    }
    const double b = glm::dot(d1, d2);
    const double denom = a * e - b * b;
    s = denom > tiny ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
    t = (b * s + f) / e;
    if (t < 0.0) {
        t = 0.0;
        s = std::clamp(-c / a, 0.0, 1.0);
    } else if (t > 1.0) {
        t = 1.0;
        s = std::clamp((b - c) / a, 0.0, 1.0);
    }
}

std::optional<Hit> collide(const Collider& a, const Collider& b) {
    const glm::dvec3 up{0.0, 0.0, 1.0};
    // Reduce every pair to a point-with-radius against a shape, with the closest points found first.
    if (a.kind == ShapeKind::box && b.kind == ShapeKind::box) {
        const glm::dvec3 d = a.a_m - b.a_m;
        const glm::dvec3 overlap = a.half_extent_m + b.half_extent_m - glm::abs(d);
        if (overlap.x <= 0 || overlap.y <= 0 || overlap.z <= 0) return std::nullopt;
        int axis = 0;
        if (overlap.y < overlap[axis]) axis = 1;
        if (overlap.z < overlap[axis]) axis = 2;
        glm::dvec3 n{0.0};
        n[axis] = d[axis] >= 0.0 ? 1.0 : -1.0;
        return Hit{0.5 * (a.a_m + b.a_m), n, overlap[axis]};
    }
    if (a.kind == ShapeKind::box || b.kind == ShapeKind::box) {
        const bool box_is_a = a.kind == ShapeKind::box;
        const Collider& box = box_is_a ? a : b;
        const Collider& other = box_is_a ? b : a;
        glm::dvec3 p = other.a_m;
        if (other.kind == ShapeKind::capsule) {
            const double t = closest_segment_parameter_to_box(other.a_m, other.b_m, box.a_m, box.half_extent_m);
            p = other.a_m + t * (other.b_m - other.a_m);
        }
        return point_box(p, other.radius_m, box.a_m, box.half_extent_m, box_is_a);
    }
    glm::dvec3 pa = a.a_m;
    glm::dvec3 pb = b.a_m;
    if (a.kind == ShapeKind::capsule && b.kind == ShapeKind::capsule) {
        double s = 0.0;
        double t = 0.0;
        closest_segment_points(a.a_m, a.b_m, b.a_m, b.b_m, s, t);
        pa = a.a_m + s * (a.b_m - a.a_m);
        pb = b.a_m + t * (b.b_m - b.a_m);
    } else if (a.kind == ShapeKind::capsule) {
        double s = 0.0;
        double t = 0.0;
        closest_segment_points(a.a_m, a.b_m, b.a_m, b.a_m, s, t);
        pa = a.a_m + s * (a.b_m - a.a_m);
    } else if (b.kind == ShapeKind::capsule) {
        double s = 0.0;
        double t = 0.0;
        closest_segment_points(a.a_m, a.a_m, b.a_m, b.b_m, s, t);
        pb = b.a_m + t * (b.b_m - b.a_m);
    }
    const glm::dvec3 axis = a.kind == ShapeKind::capsule ? a.b_m - a.a_m : up;
    const glm::dvec3 fallback = glm::length(axis) > tiny ? any_perpendicular(glm::normalize(axis)) : up;
    return spheres(pa, a.radius_m, pb, b.radius_m, fallback);
}

std::optional<Hit> collide_capsule_pin(const Collider& capsule, glm::dvec3 pin_base, const components::PinShape& pin) {
    const double r = 0.5 * pin.trunk_diameter_m;
    const glm::dvec3 trunk_top = pin_base + glm::dvec3{0, 0, pin.trunk_length_m};
    const glm::dvec3 tip = trunk_top + glm::dvec3{0, 0, pin.tip_length_m};
    double s = 0.0;
    double t = 0.0;
    closest_segment_points(capsule.a_m, capsule.b_m, pin_base, tip, s, t);
    const glm::dvec3 on_capsule = capsule.a_m + s * (capsule.b_m - capsule.a_m);
    const glm::dvec3 on_pin = pin_base + t * (tip - pin_base);
    // The cone narrows linearly from r at the trunk top to 0 at the point.
    const double height = on_pin.z - pin_base.z;
    const double pin_radius = height <= pin.trunk_length_m ? r : r * std::max(0.0, 1.0 - (height - pin.trunk_length_m) / pin.tip_length_m);
    auto hit = spheres(on_capsule, capsule.radius_m, on_pin, pin_radius, glm::dvec3{0, 0, 1});
    return hit;
}

Bounds bounds_of(const Collider& c) {
    switch (c.kind) {
    case ShapeKind::sphere: return {c.a_m - glm::dvec3{c.radius_m}, c.a_m + glm::dvec3{c.radius_m}};
    case ShapeKind::capsule:
        return {glm::min(c.a_m, c.b_m) - glm::dvec3{c.radius_m}, glm::max(c.a_m, c.b_m) + glm::dvec3{c.radius_m}};
    case ShapeKind::box: return {c.a_m - c.half_extent_m, c.a_m + c.half_extent_m};
    }
    return {c.a_m, c.a_m};
}

} // namespace ikebana::systems::collision
