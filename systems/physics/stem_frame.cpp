#include "systems/physics/stem_frame.hpp"

#include <algorithm>
#include <cmath>

namespace ikebana::systems::physics {

using components::StemFrame;
using components::StemRestShape;

namespace {

// Any unit vector across `e` (unit): for a director that has lost its way (a segment turned onto it).
glm::dvec3 any_across(glm::dvec3 e) {
    const glm::dvec3 helper = std::abs(e.x) < 0.9 ? glm::dvec3{1.0, 0.0, 0.0} : glm::dvec3{0.0, 1.0, 0.0};
    return glm::normalize(glm::cross(glm::cross(e, helper), e));
}

// `d` made unit and across `e`; any direction across it where it is along e.
[[gnu::always_inline]] inline glm::dvec3 across(glm::dvec3 d, glm::dvec3 e) {
    const glm::dvec3 p = d - glm::dot(d, e) * e;
    const double length = glm::length(p);
    return length > 1e-9 ? p * (1.0 / length) : any_across(e);
}

bool unit_direction(const std::vector<glm::dvec3>& x, std::size_t j, glm::dvec3& e, double& length) {
    const glm::dvec3 d = x[j + 1] - x[j];
    length = glm::length(d);
    if (!(length > 0.0)) return false;
    e = d * (1.0 / length);
    return true;
}

} // namespace

bool bends_have_directions(const StemRestShape& rest, const StemFrame& frame) {
    return !rest.hinge_bend_direction.empty() && rest.hinge_bend_direction.size() + 1 == frame.director.size() &&
           rest.hinge_angle_rad.size() == rest.hinge_bend_direction.size();
}

namespace {
[[gnu::always_inline]] inline glm::dvec3 carry(glm::dvec3 d, glm::dvec3 from, glm::dvec3 to) {
    const double c = glm::dot(from, to);
    if (c < -0.999999) [[unlikely]] return across(d, to); // turned back on itself: no least rotation
    const glm::dvec3 v = glm::cross(from, to);
    // Rodrigues' rotation about v by the angle between them, written without the angle.
    return d * c + glm::cross(v, d) + v * (glm::dot(v, d) / (1.0 + c));
}
} // namespace

glm::dvec3 transport(glm::dvec3 d, glm::dvec3 from, glm::dvec3 to) { return carry(d, from, to); }

StemFrame frame_along(const std::vector<glm::dvec3>& x, glm::dvec3 first, double twist_stiffness_nm2) {
    StemFrame frame;
    frame.twist_stiffness_nm2 = twist_stiffness_nm2;
    const std::size_t n = x.size() > 0 ? x.size() - 1 : 0;
    frame.director.resize(n);
    frame.segment_direction.resize(n);
    frame.held.assign(n, 0);
    frame.held_director.assign(n, glm::dvec3{0.0});
    frame.held_at.assign(n, glm::dvec3{0.0});
    frame.external_twist_nm.assign(n, 0.0);
    frame.external_twist_stiffness_nm.assign(n, 0.0);
    glm::dvec3 previous_e{0.0, 0.0, 1.0};
    glm::dvec3 d = first;
    for (std::size_t j = 0; j < n; ++j) {
        glm::dvec3 e;
        double length;
        if (!unit_direction(x, j, e, length)) e = previous_e;
        d = across(j == 0 ? d : transport(d, previous_e, e), e);
        frame.director[j] = d;
        frame.segment_direction[j] = e;
        previous_e = e;
    }
    return frame;
}

glm::dvec3 bend_vector(const std::vector<glm::dvec3>& x, std::size_t i) {
    const glm::dvec3 a = glm::normalize(x[i] - x[i - 1]);
    const glm::dvec3 b = glm::normalize(x[i + 1] - x[i]);
    const glm::dvec3 c = glm::cross(a, b);
    const double s = glm::length(c);
    if (!(s > 1e-12)) return glm::dvec3{0.0};
    return c * (std::atan2(s, glm::dot(a, b)) / s);
}

glm::dvec3 rest_bend_vector(const StemRestShape& rest, const StemFrame& frame, const std::vector<glm::dvec3>& x, std::size_t i) {
    if (!bends_have_directions(rest, frame) || i == 0 || i > rest.hinge_angle_rad.size()) return glm::dvec3{0.0};
    glm::dvec3 e;
    double length;
    if (!unit_direction(x, i - 1, e, length)) return glm::dvec3{0.0};
    const glm::dvec3 d1 = across(frame.director[i - 1], e);
    const glm::dvec2 dir = rest.hinge_bend_direction[i - 1];
    return rest.hinge_angle_rad[i - 1] * (dir.x * d1 + dir.y * glm::cross(e, d1));
}

namespace {
// A bend (rotation vector) as an angle and a direction in segment i-1's frame.
void set_rest_bend(StemRestShape& rest, const StemFrame& frame, const std::vector<glm::dvec3>& x, std::size_t i, glm::dvec3 bend) {
    glm::dvec3 e;
    double length;
    if (!unit_direction(x, i - 1, e, length)) return;
    const glm::dvec3 d1 = across(frame.director[i - 1], e);
    const glm::dvec2 in_frame{glm::dot(bend, d1), glm::dot(bend, glm::cross(e, d1))};
    const double angle = glm::length(in_frame);
    rest.hinge_angle_rad[i - 1] = angle;
    rest.hinge_bend_direction[i - 1] = angle > 1e-12 ? in_frame * (1.0 / angle) : glm::dvec2{1.0, 0.0};
}
} // namespace

void rest_bends_from_shape(const std::vector<glm::dvec3>& x, const StemFrame& frame, StemRestShape& rest) {
    const std::size_t hinges = x.size() > 2 ? x.size() - 2 : 0;
    rest.hinge_angle_rad.assign(hinges, 0.0);
    rest.hinge_bend_direction.assign(hinges, glm::dvec2{1.0, 0.0});
    if (frame.director.size() != hinges + 1) return;
    for (std::size_t i = 1; i <= hinges; ++i) set_rest_bend(rest, frame, x, i, bend_vector(x, i));
}

void add_rest_bend(StemRestShape& rest, const StemFrame& frame, const std::vector<glm::dvec3>& x, std::size_t i, glm::dvec3 bend) {
    if (!bends_have_directions(rest, frame) || i == 0 || i > rest.hinge_angle_rad.size()) return;
    glm::dvec3 was = rest_bend_vector(rest, frame, x, i);
    if (!hinge_has_direction(rest, i)) {
        // A bend without a direction lies in the plane the hinge is bent in now: it takes that
        // direction (or the added bend's, on a straight hinge) and keeps it from here on.
        const glm::dvec3 now = bend_vector(x, i);
        const glm::dvec3 side = glm::length(now) > 1e-12 ? now : bend;
        was = glm::length(side) > 0.0 ? glm::normalize(side) * rest.hinge_angle_rad[i - 1] : glm::dvec3{0.0};
    }
    set_rest_bend(rest, frame, x, i, was + bend);
}

double twist_at(const StemFrame& frame, const std::vector<glm::dvec3>& x, std::size_t i) {
    glm::dvec3 a, b;
    double la, lb;
    if (i == 0 || i >= frame.director.size() || !unit_direction(x, i - 1, a, la) || !unit_direction(x, i, b, lb)) return 0.0;
    const glm::dvec3 carried = across(transport(frame.director[i - 1], a, b), b);
    return std::atan2(glm::dot(glm::cross(carried, frame.director[i]), b), glm::dot(carried, frame.director[i]));
}

namespace {
// atan2(y, x) for the small angles a tick's twist is made of: the series to t^7 where |y| <= x / 10
// (its first omitted term is under 1e-9 of the angle), the library's elsewhere. This is on every hinge
// of every stem at 1 kHz.
double small_angle(double y, double x) {
    if (!(x > 0.0 && std::abs(y) <= 0.1 * x)) return std::atan2(y, x);
    const double t = y / x;
    const double u = t * t;
    return t * (1.0 + u * (-1.0 / 3.0 + u * (1.0 / 5.0 - u * (1.0 / 7.0))));
}

// The bend from unit a to unit b as a rotation vector (bend_vector's, from directions at hand): its
// angle from atan's series where the hinge is nearly straight (every hinge of a branch's curve), within
// 1e-12 of the library's.
glm::dvec3 bend_between(glm::dvec3 a, glm::dvec3 b) {
    const glm::dvec3 c = glm::cross(a, b);
    const double s = glm::length(c);
    if (!(s > 1e-12)) return glm::dvec3{0.0};
    const double cosine = glm::dot(a, b);
    double angle;
    if (cosine > 0.0 && s <= 0.1 * cosine) {
        const double t = s / cosine;
        const double u = t * t;
        angle = t * (1.0 + u * (-1.0 / 3.0 + u * (1.0 / 5.0 + u * (-1.0 / 7.0 + u * (1.0 / 9.0 + u * (-1.0 / 11.0))))));
    } else {
        angle = std::atan2(s, cosine);
    }
    return c * (angle / s);
}

// It has a bend with a direction (relaxed or not, such a frame is solved when it is updated).
bool frame_is_bent(const StemRestShape& rest, const StemFrame& frame) {
    if (!bends_have_directions(rest, frame)) return false;
    for (std::size_t i = 1; i <= rest.hinge_angle_rad.size(); ++i) {
        if (hinge_has_direction(rest, i) && rest.hinge_angle_rad[i - 1] > 0.0) return true;
    }
    return false;
}
} // namespace

void reserve_scratch(FrameScratch& s, std::size_t points) {
    for (auto* v : {&s.diagonal, &s.upper, &s.gradient, &s.step, &s.length, &s.twist_stiffness}) v->reserve(points);
}

void update_frame(StemFrame& frame, const std::vector<glm::dvec3>& x, const StemRestShape& rest,
                  const std::vector<double>& hinge_nm_per_rad, FrameScratch& scratch) {
    const std::size_t n = x.size() > 0 ? x.size() - 1 : 0;
    if (frame.director.size() != n) { // a stem whose points changed in number: a frame without twist along it
        const glm::dvec3 first = frame.director.empty() ? glm::dvec3{1.0, 0.0, 0.0} : frame.director.front();
        frame = frame_along(x, first, frame.twist_stiffness_nm2);
    }
    frame.segment_direction.resize(n, glm::dvec3{0.0});
    frame.held.resize(n, 0);
    frame.held_director.resize(n, glm::dvec3{0.0});
    frame.external_twist_nm.resize(n, 0.0);
    frame.held_at.resize(n, glm::dvec3{0.0});
    // A quiet frame (relaxed, no moments, its holds where they were) is updated every quiet_carry_ticks-th
    // tick only: its directors then turn with their segments in one go, and one with directed bends (a
    // branch's natural curve: every branch has one) is solved again then, as the stem's bending has
    // moved them. The parts, the next grip and the rest bends read it, and a few milliseconds late is
    // nothing to them (the rest bends carry their directors to each step's segments); solving every
    // branch's frame every tick was most of a forked branch's cost.
    bool quiet = frame.relaxed;
    for (std::size_t j = 0; j < n && quiet; ++j) {
        quiet = frame.external_twist_nm[j] == 0.0 && (frame.held[j] == 0 || frame.held_director[j] == frame.held_at[j]);
    }
    // A twig's stiffness comes with its moment: spent with it, whatever happens below.
    frame.external_twist_stiffness_nm.resize(n, 0.0);
    // Copied out, not swapped: a swap passes each stem's vector on to the next stem, and one from a short
    // stalk (a stripped leaf) would then grow on the 1 kHz lane in a long stem's frame.
    std::vector<double>& stiffness = scratch.twist_stiffness;
    stiffness.assign(frame.external_twist_stiffness_nm.begin(), frame.external_twist_stiffness_nm.end());
    std::fill(frame.external_twist_stiffness_nm.begin(), frame.external_twist_stiffness_nm.end(), 0.0);
    if (quiet && ++frame.quiet_ticks < quiet_carry_ticks) {
        std::fill(frame.held.begin(), frame.held.end(), std::uint8_t{0});
        return;
    }
    frame.quiet_ticks = 0;
    auto& length = scratch.length;
    length.assign(n, 0.0);
    // Carried with the segments' motion since the last tick, then the held ones set.
    bool pushed = false; // anything holding or twisting the frame this tick
    bool bent = false;   // a bend with a direction on it
    for (std::size_t j = 0; j < n; ++j) {
        glm::dvec3 e;
        if (!unit_direction(x, j, e, length[j])) continue;
        const glm::dvec3 old = frame.segment_direction[j];
        glm::dvec3 d = across(glm::dot(old, old) > 0.5 ? carry(frame.director[j], old, e) : frame.director[j], e);
        if (frame.held[j] != 0) {
            frame.held_at[j] = frame.held_director[j];
            // A hold that turns the bark (by more than about ten microradians) is work for the solve below;
            // one that keeps it where it was carried (the kenzan's, most ticks) is not.
            const glm::dvec3 held = across(frame.held_director[j], e);
            pushed = pushed || glm::dot(held, d) < 1.0 - 5e-11;
            d = held;
        }
        frame.director[j] = d;
        frame.segment_direction[j] = e;
        pushed = pushed || frame.external_twist_nm[j] != 0.0;
    }
    // Nothing holds, twists or bends the frame, and the last solve left no twist: nothing to solve.
    if (!pushed && frame.relaxed && !frame_is_bent(rest, frame)) return;
    // One Newton step on the twist angles phi_j (each director turned about its segment): E = sum over
    // hinges of GJ / (2 l) m_i^2 + k / 2 |b_i - b0_i|^2 - sum T_j phi_j. Turning d_j adds phi_j to m_j,
    // takes it from m_{j+1}, and turns b0_{j+1} about e_j. The Hessian is tridiagonal (the bends' part
    // Gauss-Newton, k |b0|^2, never negative): solved in O(n).
    auto& diagonal = scratch.diagonal;
    auto& upper = scratch.upper;
    auto& g = scratch.gradient;
    auto& step = scratch.step;
    diagonal.assign(n, 0.0);
    upper.assign(n, 0.0);
    g.assign(n, 0.0);
    step.assign(n, 0.0);
    const bool directed = bends_have_directions(rest, frame) && hinge_nm_per_rad.size() + 1 >= n;
    double largest = 0.0, most_twist = 0.0;
    for (std::size_t i = 1; i < n; ++i) {
        const double share = 0.5 * (length[i - 1] + length[i]);
        if (!(share > 0.0)) continue;
        const glm::dvec3 a = frame.segment_direction[i - 1], b = frame.segment_direction[i];
        // The twist at hinge i: d_{i-1} carried across the hinge (a unit vector across b) against d_i.
        const glm::dvec3 carried = carry(frame.director[i - 1], a, b);
        const double m = small_angle(glm::dot(glm::cross(carried, frame.director[i]), b), glm::dot(carried, frame.director[i]));
        const double kappa = frame.twist_stiffness_nm2 / share;
        g[i] += kappa * m;
        g[i - 1] -= kappa * m;
        diagonal[i] += kappa;
        diagonal[i - 1] += kappa;
        upper[i - 1] -= kappa;
        largest = std::max(largest, kappa);
        most_twist = std::max(most_twist, std::abs(m));
        if (directed && hinge_has_direction(rest, i) && rest.hinge_angle_rad[i - 1] > 0.0) {
            bent = true;
            const double k = hinge_nm_per_rad[i - 1];
            // The bend from a to b and the rest bend in d_{i-1}'s frame, as bend_vector and
            // rest_bend_vector have them, from the directions and directors already at hand.
            const glm::dvec3 bend = bend_between(a, b);
            const glm::dvec3 d1 = frame.director[i - 1];
            const glm::dvec2 dir = rest.hinge_bend_direction[i - 1];
            const glm::dvec3 b0 = rest.hinge_angle_rad[i - 1] * (dir.x * d1 + dir.y * glm::cross(a, d1));
            g[i - 1] -= k * glm::dot(bend - b0, glm::cross(a, b0));
            diagonal[i - 1] += k * glm::dot(b0, b0);
        }
    }
    // Without holds, moments or directed bends the twist's energy is quadratic: this one step relaxes
    // it, and until something pushes again there is nothing more to solve. With directed bends it is
    // relaxed once a step turns nothing (below).
    frame.relaxed = !pushed && !bent;
    if (!pushed && !bent && most_twist < 1e-9) return;
    const bool held_somewhere = std::any_of(frame.held.begin(), frame.held.end(), [](std::uint8_t h) { return h != 0; });
    for (std::size_t j = 0; j < n; ++j) {
        g[j] -= frame.external_twist_nm[j];
        diagonal[j] += stiffness[j];
        // A stem held nowhere turns freely as a whole: a little stiffness against turning at all keeps
        // the system regular (a millionth of the twist's).
        if (!held_somewhere) diagonal[j] += 1e-6 * (largest > 0.0 ? largest : 1.0);
    }
    for (std::size_t j = 0; j < n; ++j) {
        if (frame.held[j] == 0) continue;
        g[j] = 0.0;
        diagonal[j] = 1.0;
        upper[j] = 0.0;
        if (j > 0) upper[j - 1] = 0.0;
    }
    // Thomas' algorithm on the symmetric tridiagonal (diagonal, upper): step = -H^-1 g.
    for (std::size_t j = 1; j < n; ++j) {
        const double w = upper[j - 1] / diagonal[j - 1];
        diagonal[j] -= w * upper[j - 1];
        g[j] -= w * g[j - 1];
    }
    for (std::size_t j = n; j-- > 0;) {
        const double next = j + 1 < n ? upper[j] * step[j + 1] : 0.0;
        step[j] = -(g[j] + next) / diagonal[j];
    }
    double largest_turn = 0.0;
    for (std::size_t j = 0; j < n; ++j) {
        // At most half a radian a tick: an unheld stem with a moment on it spins, it does not jump.
        const double phi = std::clamp(step[j], -0.5, 0.5);
        if (!std::isfinite(phi) || phi == 0.0) continue;
        largest_turn = std::max(largest_turn, std::abs(phi));
        const glm::dvec3 e = frame.segment_direction[j];
        const glm::dvec3 d = frame.director[j];
        double c, s;
        if (std::abs(phi) < 0.05) { // a tick's turn: the series (first omitted terms under 3e-11), not sincos
            const double u = phi * phi;
            c = 1.0 - u * (0.5 - u * (1.0 / 24.0));
            s = phi * (1.0 - u * (1.0 / 6.0 - u * (1.0 / 120.0)));
        } else {
            c = std::cos(phi);
            s = std::sin(phi);
        }
        frame.director[j] = across(d * c + glm::cross(e, d) * s, e);
    }
    if (bent && !pushed) frame.relaxed = largest_turn < 1e-9;
    std::fill(frame.held.begin(), frame.held.end(), std::uint8_t{0});
    std::fill(frame.external_twist_nm.begin(), frame.external_twist_nm.end(), 0.0);
}

} // namespace ikebana::systems::physics
