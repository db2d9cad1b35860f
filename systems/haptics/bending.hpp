#pragma once
// Both-hand bending (paper 2.4, Figures 6-8). The two index fingers are the supports A and B, L apart;
// the thumbs push at the middle C until the two halves make the angle theta (pi: straight). Eq. 4 is
// the displacement of the stem at distance x from A, Eq. 5 the force at C. They are the simply
// supported beam under a central load (deflection F x (3L^2 - 4x^2) / 48EI) with the mid-span
// deflection fixed by the geometry, (L/2) / tan(theta/2).
#include <cstddef>
#include <vector>

#include "components/stem.hpp"

namespace ikebana::systems::bending {

// Eq. 4: displacement at x in [0, L] (metres), perpendicular to the line A-B, towards C.
[[nodiscard]] double displacement(double x, double span, double theta);
// Eq. 5: F^b = 24 E I / (L^2 tan(theta/2)), for 0 < theta < pi (N).
[[nodiscard]] double force(double ei, double span, double theta);

// Bending beyond `set_threshold` (radians of bend, pi - theta) leaves a permanent set: the rest
// angles of the hinges between the supports take up the excess, spread evenly, so the branch stays
// bent by (bend - threshold) after release. Returns the set added (radians, 0 below the threshold).
// With the stem's frame and points, each hinge's set is added in the direction it is bent now, held in
// the frame: the branch stays bent toward the side it was bent, however it is turned or carried after.
double apply_permanent_set(components::StemRestShape& rest, std::size_t first_hinge, std::size_t last_hinge,
                           double theta, double set_threshold, const components::StemFrame* frame = nullptr,
                           const std::vector<glm::dvec3>* points = nullptr);

} // namespace ikebana::systems::bending
