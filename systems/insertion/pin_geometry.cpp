#include "systems/insertion/pin_geometry.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ikebana::systems::insertion {

using components::Kenzan;
using components::PinContact;
using components::PinShape;

namespace {
constexpr double eps = 1e-12;
constexpr double unbounded = std::numeric_limits<double>::infinity();

Interval intersect(Interval a, Interval b) { return {std::max(a.lo, b.lo), std::min(a.hi, b.hi)}; }
} // namespace

glm::dvec3 lean_direction(glm::dvec3 axis) {
    const glm::dvec3 h{axis.x, axis.y, 0.0};
    const double len = glm::length(h);
    return len > 1e-9 ? h / len : glm::dvec3{1.0, 0.0, 0.0};
}

std::optional<Interval> vertical_chord(const StemEnd& stem, double x, double y, double radius, double from, double to) {
    // Points on the line: (x, y, t). With w = point - bottom: axial a(t) = c.u + t u_z, and the squared
    // distance from the axis is A t^2 + B t + C.
    const glm::dvec3& u = stem.axis;
    const glm::dvec3 c{x - stem.bottom_m.x, y - stem.bottom_m.y, -stem.bottom_m.z};
    const double cu = glm::dot(c, u);
    const double a_coef = 1.0 - u.z * u.z;
    const double b_coef = 2.0 * (c.z - cu * u.z);
    const double c_coef = glm::dot(c, c) - cu * cu - radius * radius;
    Interval inside{-unbounded, unbounded};
    if (a_coef < eps) { // stem vertical: the distance from the axis does not change with height
        if (c_coef > 0.0) return std::nullopt;
    } else {
        const double disc = b_coef * b_coef - 4.0 * a_coef * c_coef;
        if (disc <= 0.0) return std::nullopt;
        const double root = std::sqrt(disc);
        inside = {(-b_coef - root) / (2.0 * a_coef), (-b_coef + root) / (2.0 * a_coef)};
    }
    Interval slab{-unbounded, unbounded};
    if (std::abs(u.z) < eps) { // stem horizontal: the axial position does not change with height
        if (cu < from || cu > to) return std::nullopt;
    } else {
        const double t0 = (from - cu) / u.z;
        const double t1 = (to - cu) / u.z;
        slab = {std::min(t0, t1), std::max(t0, t1)};
    }
    const Interval both = intersect(inside, slab);
    if (both.length() <= 0.0) return std::nullopt;
    return both;
}

std::optional<PinContact> pin_contact(const StemEnd& stem, glm::dvec3 base, const PinShape& pin) {
    const auto chord = vertical_chord(stem, base.x, base.y, stem.radius_m, stem.seat_loss_m, stem.length_m);
    if (!chord) return std::nullopt;
    const Interval trunk{base.z, base.z + pin.trunk_length_m};
    const Interval tip{trunk.hi, trunk.hi + pin.tip_length_m};
    PinContact contact{};
    contact.trunk_m = intersect(*chord, trunk).length();
    contact.tip_m = intersect(*chord, tip).length();
    if (contact.trunk_m + contact.tip_m <= 0.0) return std::nullopt;
    if (stem.pith_radius_m > 0.0) {
        if (const auto pith = vertical_chord(stem, base.x, base.y, stem.pith_radius_m, stem.seat_loss_m, stem.length_m)) {
            contact.trunk_in_pith_m = intersect(*pith, trunk).length();
            contact.tip_in_pith_m = intersect(*pith, tip).length();
        }
    }
    return contact;
}

std::vector<PinContact> engaged_pins(const StemEnd& stem, const Kenzan& k) {
    std::vector<PinContact> out;
    engaged_pins(stem, k, out);
    return out;
}

void engaged_pins(const StemEnd& stem, const Kenzan& k, std::vector<PinContact>& out) {
    out.clear();
    // The footprint on the pin field: the stem end's bounding box over the pins' height range.
    const double top = k.origin_m.z + k.pin_height_m();
    // Only the part of the end whose axis is below the tips plus the stem's radius can touch a pin: the
    // rest of it is left out of the footprint (a 5 cm end at 45 degrees spanned 9 x 9 pins, most of them
    // far under the stem's upper part).
    double reach_m = stem.length_m;
    if (stem.axis.z > 0.0) reach_m = std::clamp((top + stem.radius_m - stem.bottom_m.z) / stem.axis.z, 0.0, stem.length_m);
    const glm::dvec3 far = stem.bottom_m + stem.axis * reach_m;
    glm::dvec2 lo = glm::min(glm::dvec2(stem.bottom_m), glm::dvec2(far)) - glm::dvec2(stem.radius_m);
    glm::dvec2 hi = glm::max(glm::dvec2(stem.bottom_m), glm::dvec2(far)) + glm::dvec2(stem.radius_m);
    if (std::min(stem.bottom_m.z, far.z) - stem.radius_m > top) return;
    const auto range = k.pins_within(lo, hi);
    for (auto row = range.row_lo; row <= range.row_hi; ++row) {
        for (auto col = range.column_lo; col <= range.column_hi; ++col) {
            if (!k.has_pin(col, row)) continue;
            if (auto contact = pin_contact(stem, k.pin_base(col, row), k.pin)) {
                contact->pin = row * k.columns + col;
                out.push_back(*contact);
            }
        }
    }
}

glm::dvec3 assign_lever_arms(const StemEnd& stem, const Kenzan& k, std::vector<PinContact>& pins) {
    const glm::dvec3 h = lean_direction(stem.axis);
    const double top = k.origin_m.z + k.pin_height_m();
    // Where the axis crosses the pin-top plane, and the footprint's far edge in the lean direction.
    const double sin_elevation = std::max(std::abs(stem.axis.z), 0.05);
    const double t = std::abs(stem.axis.z) > eps ? (top - stem.bottom_m.z) / stem.axis.z : 0.0;
    const glm::dvec3 centre = stem.bottom_m + std::max(t, 0.0) * stem.axis;
    const glm::dvec3 edge = glm::dvec3{centre.x, centre.y, top} + h * (stem.radius_m / sin_elevation);
    for (auto& p : pins) {
        const auto column = p.pin % k.columns;
        const auto row = p.pin / k.columns;
        const glm::dvec3 base = k.pin_base(column, row);
        p.lever_m = std::max(0.0, glm::dot(glm::dvec2(edge) - glm::dvec2(base), glm::dvec2(h)));
    }
    return edge;
}

} // namespace ikebana::systems::insertion
