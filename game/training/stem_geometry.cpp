#include "game/training/stem_geometry.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "game/training/form_score.hpp"

namespace ikebana::game {

namespace training {

double wrap_deg(double a) {
    a = std::fmod(a + 180.0, 360.0);
    if (a < 0) a += 360.0;
    return a - 180.0;
}

glm::dvec3 tip_of(const ArrangementStem& s) {
    if (!s.path_m.empty()) return s.path_m.back();
    return glm::dvec3(s.base_m, 0.0) + lesson_direction(s.tilt_rad, s.azimuth_rad) * s.length_m;
}

std::vector<glm::dvec3> polyline(const ArrangementStem& s) {
    std::vector<glm::dvec3> p{glm::dvec3(s.base_m, 0.0)};
    if (s.path_m.empty()) p.push_back(tip_of(s));
    else p.insert(p.end(), s.path_m.begin(), s.path_m.end());
    return p;
}

std::optional<glm::dvec2> at_height(const std::vector<glm::dvec3>& p, double z) {
    for (std::size_t i = 1; i < p.size(); ++i) {
        const double z0 = p[i - 1].z, z1 = p[i].z;
        if ((z0 <= z && z <= z1) || (z1 <= z && z <= z0)) {
            const double t = std::abs(z1 - z0) < 1e-12 ? 0.0 : (z - z0) / (z1 - z0);
            return glm::dvec2(p[i - 1] + (p[i] - p[i - 1]) * t);
        }
    }
    return std::nullopt;
}

double outside_region(glm::dvec2 b, KenzanRegion r, glm::dvec2 size) {
    const glm::dvec2 h = 0.5 * size;
    // Each region as a box in the face; "front" is toward the viewer (-y). Halves overlap by a pin pitch
    // around the middle lines, so a stem on the line counts for both sides. Outward a region has no
    // edge: a stem leaning out of its part crosses the pins' tops beyond the kenzan (a hikae at 70
    // degrees, 36 mm out) with its bottom in the pins, and "enters the front right; the form puts it in
    // the front right: move its base 17 mm toward the front right" helped nobody.
    const double m = 0.004;
    constexpr double far = std::numeric_limits<double>::infinity();
    double x0 = -far, x1 = far, y0 = -far, y1 = far;
    switch (r) {
    case KenzanRegion::any: break;
    case KenzanRegion::centre: x0 = -h.x / 2, x1 = h.x / 2, y0 = -h.y / 2, y1 = h.y / 2; break;
    case KenzanRegion::front: y1 = m; break;
    case KenzanRegion::back: y0 = -m; break;
    case KenzanRegion::left: x1 = m; break;
    case KenzanRegion::right: x0 = -m; break;
    case KenzanRegion::front_left: x1 = m, y1 = m; break;
    case KenzanRegion::front_right: x0 = -m, y1 = m; break;
    case KenzanRegion::back_left: x1 = m, y0 = -m; break;
    case KenzanRegion::back_right: x0 = -m, y0 = -m; break;
    }
    const double dx = std::max({x0 - b.x, 0.0, b.x - x1});
    const double dy = std::max({y0 - b.y, 0.0, b.y - y1});
    return std::hypot(dx, dy);
}

std::string where_on_kenzan(glm::dvec2 b, glm::dvec2 size) {
    const double third_x = size.x / 6.0, third_y = size.y / 6.0;
    const std::string fb = b.y < -third_y ? "front" : b.y > third_y ? "back" : "";
    const std::string lr = b.x < -third_x ? "left" : b.x > third_x ? "right" : "";
    if (fb.empty() && lr.empty()) return "the centre";
    if (fb.empty()) return "the " + lr;
    if (lr.empty()) return "the " + fb;
    return "the " + fb + " " + lr;
}

bool segments_cross(glm::dvec2 a0, glm::dvec2 a1, glm::dvec2 b0, glm::dvec2 b1, glm::dvec2& at) {
    const glm::dvec2 r = a1 - a0, s = b1 - b0;
    const double d = r.x * s.y - r.y * s.x;
    if (std::abs(d) < 1e-15) return false;
    const glm::dvec2 q = b0 - a0;
    const double t = (q.x * s.y - q.y * s.x) / d;
    const double u = (q.x * r.y - q.y * r.x) / d;
    if (t < 0 || t > 1 || u < 0 || u > 1) return false;
    at = a0 + r * t;
    return true;
}

} // namespace training

double water_level_m(const LessonDef& l, const KenzanFootprint& k) {
    if (l.container.shape == ContainerShape::vase) return 0.0;
    return l.container.water_depth_m - k.plate_thickness_m;
}

double outside_place_m(glm::dvec2 at_m, KenzanRegion region, const KenzanFootprint& kenzan) { return training::outside_region(at_m, region, kenzan.size_m); }

double in_pins_along_m(double depth_m, double tilt_rad) {
    constexpr double steepest_rad = 80.0 * 3.14159265358979323846 / 180.0;
    return depth_m / std::cos(std::clamp(std::abs(tilt_rad), 0.0, steepest_rad));
}

double lean_above_rise_rad(const ArrangementStem& s) {
    if (s.path_m.size() != 2) return 0.0;
    return std::acos(std::clamp(glm::normalize(s.path_m[1] - s.path_m[0]).z, -1.0, 1.0));
}

} // namespace ikebana::game
