#pragma once
// The stem's material frame (components::StemFrame): which way its bark faces along its length, so
// that a bend keeps its direction about the stem and a stem can be twisted. Discrete elastic rods
// (Bergou et al. 2008) with quasi-static twist: positions come from the spring stem (stem_dynamics);
// after each tick the directors are carried with their segments and turned to the twist of least
// energy, given the stem's shape, the rest bends' directions and what holds the stem.
#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "components/stem.hpp"

namespace ikebana::systems::physics {

// The rest shape's bends can be read in this frame: a direction for every hinge, a director for every
// segment (some directions may be zero).
[[nodiscard]] bool bends_have_directions(const components::StemRestShape& rest, const components::StemFrame& frame);
// Hinge i's (1..n-1) rest bend has a direction of its own; a zero one takes the plane it is bent in.
[[nodiscard]] inline bool hinge_has_direction(const components::StemRestShape& rest, std::size_t i) {
    const glm::dvec2 d = rest.hinge_bend_direction[i - 1];
    return d.x != 0.0 || d.y != 0.0;
}

// `d` carried from a segment along `from` to one along `to` by the least rotation (parallel
// transport); both unit.
[[nodiscard]] glm::dvec3 transport(glm::dvec3 d, glm::dvec3 from, glm::dvec3 to);

// A frame without twist along the stem as it lies: `first` (projected across the first segment; any
// direction across it if it is along it) carried up segment by segment.
[[nodiscard]] components::StemFrame frame_along(const std::vector<glm::dvec3>& points, glm::dvec3 first, double twist_stiffness_nm2);

// The bend at hinge i (1..n-1) as a rotation vector: angle times the unit normal of e_{i-1} x e_i.
[[nodiscard]] glm::dvec3 bend_vector(const std::vector<glm::dvec3>& points, std::size_t i);

// The rest bend at hinge i as a rotation vector in the room, from its angle, its direction and the
// frame of the segment below it. Zero where the rest shape has no directions (or this hinge none).
[[nodiscard]] glm::dvec3 rest_bend_vector(const components::StemRestShape& rest, const components::StemFrame& frame,
                                          const std::vector<glm::dvec3>& points, std::size_t i);

// Makes the stem's present shape its rest shape's bends: angles and their directions in `frame`.
void rest_bends_from_shape(const std::vector<glm::dvec3>& points, const components::StemFrame& frame,
                           components::StemRestShape& rest);

// Adds `bend` (a rotation vector in the room) to hinge i's rest bend, keeping it in the frame: a
// permanent set made in one direction stays in that direction on the stem. A rest bend without a
// direction is first taken as lying in the plane the hinge is bent in now.
void add_rest_bend(components::StemRestShape& rest, const components::StemFrame& frame, const std::vector<glm::dvec3>& points,
                   std::size_t i, glm::dvec3 bend);

// The twist at hinge i (1..n-1): the angle from segment i-1's director carried across the hinge to
// segment i's, about segment i, right-handed. Summed over the hinges between two segments it is how
// far the stem is twisted between them.
[[nodiscard]] double twist_at(const components::StemFrame& frame, const std::vector<glm::dvec3>& points, std::size_t i);

// A quiet frame (see update_frame) is carried once in this many ticks.
inline constexpr std::uint8_t quiet_carry_ticks = 8;

struct FrameScratch {
    std::vector<double> diagonal, upper, gradient, step, length;
    std::vector<double> twist_stiffness; // this tick's StemFrame::external_twist_stiffness_nm
};

// One tick of the frame: the directors carried with their segments' motion, held ones set where they
// are held, the rest turned by one Newton step toward the least energy of twist (G J over each hinge's
// share of length), of the rest bends' directions (the hinges' k) and of the external twisting moments.
// The holds and the external moments are consumed. `hinge_nm_per_rad`: the stem's hinge springs.
// Room for a stem of up to `points` points, sized once when the scene loads.
void reserve_scratch(FrameScratch& scratch, std::size_t points);

void update_frame(components::StemFrame& frame, const std::vector<glm::dvec3>& points, const components::StemRestShape& rest,
                  const std::vector<double>& hinge_nm_per_rad, FrameScratch& scratch);

} // namespace ikebana::systems::physics
