#pragma once
// Which kenzan pins are inside a stem, and how much of each: computed from geometry, not assumed.
// The stem end is a solid cylinder (radius r, its bottom face perpendicular to the axis); each pin a
// vertical line from the base plate, a cylindrical trunk then a cone tip (Figure 10). For every pin
// under the stem's footprint the length of the pin inside the stem is the intersection of three
// intervals along the pin: inside the cylinder (a quadratic in height), between the bottom face and
// the top of the considered length (linear), and on the pin itself. The same with the pith radius
// gives the pith part (hard branches, Figure 11).
#include <optional>
#include <vector>

#include <glm/glm.hpp>

#include "components/insertion.hpp"
#include "components/kenzan.hpp"

namespace ikebana::systems::insertion {

struct StemEnd {
    glm::dvec3 bottom_m;   // centre of the bottom face
    glm::dvec3 axis;       // unit, from the bottom towards the top
    double radius_m;
    double pith_radius_m;  // 0 for a soft branch
    double seat_loss_m;    // a split bottom grips only from this far up the axis
    double length_m;       // how much of the stem to consider (longer than any pin)
};

struct Interval {
    double lo;
    double hi;
    [[nodiscard]] double length() const noexcept { return hi > lo ? hi - lo : 0.0; }
};

// Heights z (absolute) at which the vertical line through (x, y) is inside the cylinder of radius
// `radius` around the stem axis, between axial positions [from, to] measured from the bottom face.
std::optional<Interval> vertical_chord(const StemEnd& stem, double x, double y, double radius, double from, double to);

// The contact of one pin (no force yet), or nothing if the pin is not inside the stem.
std::optional<components::PinContact> pin_contact(const StemEnd& stem, glm::dvec3 pin_base, const components::PinShape& pin);

// Every engaged pin of the kenzan, found through its grid (only pins under the footprint are tried).
std::vector<components::PinContact> engaged_pins(const StemEnd& stem, const components::Kenzan& kenzan);
// The same into `out` (cleared first), keeping its memory: the 1 kHz tracking calls it for every stem.
void engaged_pins(const StemEnd& stem, const components::Kenzan& kenzan, std::vector<components::PinContact>& out);

// Lever arm of each pin about the tipping edge: the stem tips towards the horizontal direction it
// leans, about the far edge of its footprint on the pin-top plane; a pin on the other side must slide
// out of the stem by (lever x rotation). Fills PinContact::lever_m; returns the tipping edge point.
glm::dvec3 assign_lever_arms(const StemEnd& stem, const components::Kenzan& kenzan, std::vector<components::PinContact>& pins);

// The horizontal direction the stem leans (x, y, 0), or +x for a vertical stem.
glm::dvec3 lean_direction(glm::dvec3 axis);

} // namespace ikebana::systems::insertion
