#include "systems/haptics/bending.hpp"

#include "systems/physics/stem_frame.hpp"

#include <algorithm>
#include <cmath>

namespace ikebana::systems::bending {

double displacement(double x, double span, double theta) {
    if (span <= 0.0 || !(theta > 0.0) || theta >= M_PI) return 0.0;
    const double u = std::clamp(x, 0.0, span);
    const double from_nearest_support = u <= 0.5 * span ? u : span - u; // Eq. 4's two halves
    const double r = from_nearest_support / span;
    return span / (2.0 * std::tan(0.5 * theta)) * (3.0 * r - 4.0 * r * r * r);
}

double force(double ei, double span, double theta) {
    if (span <= 0.0 || !(theta > 0.0) || theta >= M_PI) return 0.0;
    return 24.0 * ei / (span * span * std::tan(0.5 * theta));
}

double apply_permanent_set(components::StemRestShape& rest, std::size_t first_hinge, std::size_t last_hinge,
                           double theta, double set_threshold, const components::StemFrame* frame,
                           const std::vector<glm::dvec3>* points) {
    const double bend = M_PI - theta;
    if (bend <= set_threshold || rest.hinge_angle_rad.empty()) return 0.0;
    last_hinge = std::min(last_hinge, rest.hinge_angle_rad.size() - 1);
    if (first_hinge > last_hinge) return 0.0;
    const double excess = bend - set_threshold;
    const double per_hinge = excess / static_cast<double>(last_hinge - first_hinge + 1);
    const bool directed = frame && points && physics::bends_have_directions(rest, *frame) && points->size() == frame->director.size() + 1;
    for (std::size_t i = first_hinge; i <= last_hinge; ++i) {
        const glm::dvec3 now = directed ? physics::bend_vector(*points, i + 1) : glm::dvec3{0.0};
        const double angle = glm::length(now);
        if (angle > 1e-9) physics::add_rest_bend(rest, *frame, *points, i + 1, now * (per_hinge / angle));
        else rest.hinge_angle_rad[i] += per_hinge;
    }
    return excess;
}

} // namespace ikebana::systems::bending
