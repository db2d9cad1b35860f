#include "systems/physics/stem_dynamics.hpp"

#include <algorithm>
#include <cmath>

namespace ikebana::systems::physics {

using components::StemClamp;
using components::StemPoints;
using components::StemRestShape;
using components::StemSprings;

namespace {

constexpr std::size_t band_points = 2;               // a hinge couples P_{i-1} with P_{i+1}
constexpr std::size_t bandwidth = 3 * band_points + 2; // in scalar unknowns

// Below this |e_i x e_i+1| the bend plane is undefined; the hinge is taken as straight.
constexpr double straight_sine = 1e-12;

struct Bend {
    double angle = 0.0;
    glm::dvec3 normal{0.0};
    bool has_plane = false;
};

Bend bend_between(glm::dvec3 e_a, glm::dvec3 e_b) {
    const glm::dvec3 c = glm::cross(e_a, e_b);
    const double s = glm::length(c);
    Bend bend;
    bend.angle = std::atan2(s, glm::dot(e_a, e_b));
    if (s > straight_sine) {
        bend.normal = c / s;
        bend.has_plane = true;
    }
    return bend;
}

bool clamp_active(const StemClamp* clamp) { return clamp != nullptr && clamp->engaged; }

// Lower band of a symmetric matrix: entry (i, j) with i - bandwidth <= j <= i.
struct Band {
    std::vector<double>& data;
    std::size_t n;
    double& at(std::size_t i, std::size_t j) { return data[i * (bandwidth + 1) + (j + bandwidth - i)]; }
    // Adds v to (i, j) and, by symmetry, (j, i): only the lower triangle is stored.
    void add(std::size_t i, std::size_t j, double v) {
        if (j > i) std::swap(i, j);
        at(i, j) += v;
    }
};

void add_block(Band& band, std::size_t p, std::size_t q, const glm::dmat3& block, double scale) {
    for (std::size_t r = 0; r < 3; ++r) {
        for (std::size_t c = 0; c < 3; ++c) {
            const std::size_t i = 3 * p + r;
            const std::size_t j = 3 * q + c;
            if (p == q && j > i) continue; // diagonal block: lower half only (symmetric)
            if (p != q && p < q) continue; // off-diagonal: store the lower block only
            band.add(i, j, scale * block[static_cast<glm::length_t>(c)][static_cast<glm::length_t>(r)]);
        }
    }
}

// In-place banded Cholesky factorisation and solve of A x = b (A symmetric positive definite).
bool cholesky_solve(Band& a, std::vector<double>& b) {
    const std::size_t n = a.n;
    for (std::size_t i = 0; i < n; ++i) {
        const std::size_t j0 = i >= bandwidth ? i - bandwidth : 0;
        for (std::size_t j = j0; j <= i; ++j) {
            double sum = a.at(i, j);
            const std::size_t k0 = std::max(j0, j >= bandwidth ? j - bandwidth : std::size_t{0});
            for (std::size_t k = k0; k < j; ++k) sum -= a.at(i, k) * a.at(j, k);
            if (i == j) {
                if (!(sum > 0.0)) return false;
                a.at(i, i) = std::sqrt(sum);
            } else {
                a.at(i, j) = sum / a.at(j, j);
            }
        }
    }
    for (std::size_t i = 0; i < n; ++i) { // L y = b
        const std::size_t k0 = i >= bandwidth ? i - bandwidth : 0;
        double sum = b[i];
        for (std::size_t k = k0; k < i; ++k) sum -= a.at(i, k) * b[k];
        b[i] = sum / a.at(i, i);
    }
    for (std::size_t ii = n; ii-- > 0;) { // L^T x = y
        double sum = b[ii];
        const std::size_t k1 = std::min(n, ii + bandwidth + 1);
        for (std::size_t k = ii + 1; k < k1; ++k) sum -= a.at(k, ii) * b[k];
        b[ii] = sum / a.at(ii, ii);
    }
    return true;
}

} // namespace

double hinge_angle(const StemPoints& points, std::size_t i) {
    const auto& x = points.position_m;
    return bend_between(glm::normalize(x[i] - x[i - 1]), glm::normalize(x[i + 1] - x[i])).angle;
}

void stem_forces(const StemPoints& points, const StemRestShape& rest, const StemSprings& springs,
                 const StemClamp* clamp, glm::dvec3 gravity, std::vector<glm::dvec3>& f) {
    const auto& x = points.position_m;
    const std::size_t count = x.size();
    f.assign(count, glm::dvec3{0.0});
    for (std::size_t p = 0; p < count; ++p) f[p] = points.mass_kg[p] * gravity + points.external_force_n[p];

    // Eq. 1: structure springs.
    for (std::size_t i = 1; i < count; ++i) {
        const glm::dvec3 d = x[i] - x[i - 1];
        const double length = glm::length(d);
        if (length <= 0.0) continue;
        const glm::dvec3 e = d / length;
        const glm::dvec3 spring = springs.axial_n_per_m[i - 1] * (length - rest.segment_length_m[i - 1]) * e;
        f[i - 1] += spring;
        f[i] -= spring;
    }
    // Eq. 2-3: hinge springs at P1..Pn-1, with the coupling force on P_i.
    for (std::size_t i = 1; i + 1 < count; ++i) {
        const glm::dvec3 d_in = x[i] - x[i - 1];
        const glm::dvec3 d_out = x[i + 1] - x[i];
        const double l_in = glm::length(d_in);
        const double l_out = glm::length(d_out);
        if (l_in <= 0.0 || l_out <= 0.0) continue;
        const glm::dvec3 e_in = d_in / l_in;
        const glm::dvec3 e_out = d_out / l_out;
        const Bend bend = bend_between(e_in, e_out);
        if (!bend.has_plane) continue; // straight: zero torque at theta0 = 0, undefined plane otherwise
        double torque = springs.hinge_nm_per_rad[i - 1] * (bend.angle - rest.hinge_angle_rad[i - 1]);
        // A naturally bent hinge (a branch's curve) pulled nearly straight: its plane, the direction of
        // the torque, turns arbitrarily as the angle goes to zero, while the torque toward the rest bend
        // stays large. Pushed in a new direction each step, the stem gained energy until it flew (a
        // cherry branch held at 45 degrees with its curve down). Below half its rest angle the torque
        // fades with the angle, to none when straight, where the plane is undefined.
        const double rest_angle = rest.hinge_angle_rad[i - 1];
        if (rest_angle > 0.0 && bend.angle < 0.5 * rest_angle) torque *= bend.angle / (0.5 * rest_angle);
        const glm::dvec3 f_prev = torque * glm::cross(bend.normal, -e_in) / l_in;
        const glm::dvec3 f_next = -torque * glm::cross(bend.normal, e_out) / l_out;
        f[i - 1] += f_prev;
        f[i + 1] += f_next;
        f[i] -= f_prev + f_next;
    }
    // The clamp's root hinge works like Eq. 3 with the clamp direction in place of e_i.
    if (clamp_active(clamp) && count >= 2) {
        const glm::dvec3 d = x[1] - x[0];
        const double l = glm::length(d);
        if (l > 0.0) {
            const glm::dvec3 e = d / l;
            const Bend bend = bend_between(clamp->direction, e);
            if (bend.has_plane) {
                const glm::dvec3 f_next = -clamp->hinge_nm_per_rad * bend.angle * glm::cross(bend.normal, e) / l;
                f[1] += f_next;
                f[0] -= f_next;
            }
        }
    }
}

StemEnergy stem_energy(const StemPoints& points, const StemRestShape& rest, const StemSprings& springs,
                       const StemClamp* clamp, glm::dvec3 gravity) {
    const auto& x = points.position_m;
    StemEnergy energy;
    for (std::size_t p = 0; p < x.size(); ++p) {
        energy.kinetic_j += 0.5 * points.mass_kg[p] * glm::dot(points.velocity_m_s[p], points.velocity_m_s[p]);
        energy.gravitational_j -= points.mass_kg[p] * glm::dot(gravity, x[p]);
    }
    for (std::size_t i = 1; i < x.size(); ++i) {
        const double stretch = glm::length(x[i] - x[i - 1]) - rest.segment_length_m[i - 1];
        energy.elastic_j += 0.5 * springs.axial_n_per_m[i - 1] * stretch * stretch;
    }
    for (std::size_t i = 1; i + 1 < x.size(); ++i) {
        const double dtheta = hinge_angle(points, i) - rest.hinge_angle_rad[i - 1];
        energy.elastic_j += 0.5 * springs.hinge_nm_per_rad[i - 1] * dtheta * dtheta;
    }
    if (clamp_active(clamp) && x.size() >= 2) {
        const double theta = bend_between(clamp->direction, glm::normalize(x[1] - x[0])).angle;
        energy.elastic_j += 0.5 * clamp->hinge_nm_per_rad * theta * theta;
    }
    return energy;
}

std::size_t stable_substeps(const StemPoints& points, const StemRestShape& rest, const StemSprings& springs, const StemClamp* clamp, double dt) {
    // The diagonal of M^-1 H for the hinges (each pulls its middle point with k (1/l_in + 1/l_out)^2)
    // bounds the fastest bending mode from below within a factor of about 2: enough to choose a count.
    double omega_squared = 0.0;
    const std::size_t count = points.position_m.size();
    for (std::size_t i = 1; i + 1 < count && i - 1 < springs.hinge_nm_per_rad.size(); ++i) {
        const double c = 1.0 / rest.segment_length_m[i - 1] + 1.0 / rest.segment_length_m[i];
        if (points.mass_kg[i] > 0.0) omega_squared = std::max(omega_squared, springs.hinge_nm_per_rad[i - 1] * c * c / points.mass_kg[i]);
    }
    if (clamp_active(clamp) && count >= 2 && points.mass_kg[1] > 0.0) {
        const double c = 1.0 / rest.segment_length_m[0];
        omega_squared = std::max(omega_squared, clamp->hinge_nm_per_rad * c * c / points.mass_kg[1]);
    }
    const double steps = std::ceil(std::sqrt(omega_squared) * dt / max_omega_dt);
    if (!std::isfinite(steps) || steps <= 1.0) return 1;
    return std::min(max_substeps, static_cast<std::size_t>(steps));
}

bool step_stem(StemPoints& points, const StemRestShape& rest, const StemSprings& springs, const StemClamp* clamp,
               glm::dvec3 gravity, double dt, StemSolverScratch& scratch) {
    auto& x = points.position_m;
    auto& v = points.velocity_m_s;
    const std::size_t count = x.size();
    const std::size_t n = 3 * count;
    const bool clamped = clamp_active(clamp);
    auto is_fixed = [&](std::size_t p) { return points.pinned[p] != 0 || (clamped && p == 0); };

    stem_forces(points, rest, springs, clamp, gravity, scratch.force);
    const auto& f = scratch.force;

    // H: positive semi-definite approximation of the energy Hessian, banded.
    scratch.band.assign(n * (bandwidth + 1), 0.0);
    Band h{scratch.band, n};
    for (std::size_t i = 1; i < count; ++i) {
        const glm::dvec3 d = x[i] - x[i - 1];
        const double length = glm::length(d);
        if (length <= 0.0) continue;
        const glm::dvec3 e = d / length;
        const double k = springs.axial_n_per_m[i - 1];
        const double transverse = std::max(0.0, 1.0 - rest.segment_length_m[i - 1] / length);
        const glm::dmat3 outer = glm::outerProduct(e, e);
        const glm::dmat3 block = k * (outer + transverse * (glm::dmat3(1.0) - outer));
        add_block(h, i - 1, i - 1, block, 1.0);
        add_block(h, i, i, block, 1.0);
        add_block(h, i, i - 1, block, -1.0);
    }
    auto add_bending = [&](std::size_t first, const double* c, std::size_t terms, double k) {
        for (std::size_t a = 0; a < terms; ++a) {
            for (std::size_t b = 0; b <= a; ++b) {
                const double value = k * c[a] * c[b];
                for (std::size_t r = 0; r < 3; ++r) h.add(3 * (first + a) + r, 3 * (first + b) + r, value);
            }
        }
    };
    for (std::size_t i = 1; i + 1 < count; ++i) {
        const double l_in = rest.segment_length_m[i - 1];
        const double l_out = rest.segment_length_m[i];
        const double c[3] = {1.0 / l_in, -(1.0 / l_in + 1.0 / l_out), 1.0 / l_out};
        add_bending(i - 1, c, 3, springs.hinge_nm_per_rad[i - 1]);
    }
    if (clamped && count >= 2) {
        const double l = rest.segment_length_m[0];
        const double c[2] = {-1.0 / l, 1.0 / l};
        add_bending(0, c, 2, clamp->hinge_nm_per_rad);
    }

    // rhs = h (f - (beta + h) H v - alpha M v), before H becomes the system matrix.
    const double beta = springs.stiffness_damping_s;
    const double alpha = springs.air_drag_per_s;
    scratch.rhs.assign(n, 0.0);
    for (std::size_t i = 0; i < n; ++i) {
        const std::size_t j0 = i >= bandwidth ? i - bandwidth : 0;
        for (std::size_t j = j0; j <= i; ++j) {
            const double hij = h.at(i, j);
            if (hij == 0.0) continue;
            scratch.rhs[i] += hij * v[j / 3][static_cast<glm::length_t>(j % 3)];
            if (j != i) scratch.rhs[j] += hij * v[i / 3][static_cast<glm::length_t>(i % 3)];
        }
    }
    for (std::size_t i = 0; i < n; ++i) {
        const std::size_t p = i / 3;
        const auto axis = static_cast<glm::length_t>(i % 3);
        const double m = points.mass_kg[p];
        scratch.rhs[i] = dt * (f[p][axis] - (beta + dt) * scratch.rhs[i] - alpha * m * v[p][axis]);
    }
    // H itself, kept for the end-of-step forces below.
    scratch.stiffness = scratch.band;
    // A = M (1 + h alpha) + (h beta + h^2) H; fixed points become identity rows with zero change.
    const double stiffness_scale = dt * beta + dt * dt;
    for (std::size_t i = 0; i < n; ++i) {
        const std::size_t j0 = i >= bandwidth ? i - bandwidth : 0;
        for (std::size_t j = j0; j <= i; ++j) h.at(i, j) *= stiffness_scale;
        h.at(i, i) += points.mass_kg[i / 3] * (1.0 + dt * alpha);
    }
    for (std::size_t p = 0; p < count; ++p) {
        if (!is_fixed(p)) continue;
        for (std::size_t r = 0; r < 3; ++r) {
            const std::size_t i = 3 * p + r;
            const std::size_t j0 = i >= bandwidth ? i - bandwidth : 0;
            for (std::size_t j = j0; j < i; ++j) h.at(i, j) = 0.0;
            for (std::size_t k = i + 1; k < std::min(n, i + bandwidth + 1); ++k) h.at(k, i) = 0.0;
            h.at(i, i) = 1.0;
            scratch.rhs[i] = 0.0;
        }
    }
    if (!cholesky_solve(h, scratch.rhs)) return false;
    for (std::size_t i = 0; i < n; ++i) {
        if (!std::isfinite(scratch.rhs[i])) return false;
    }
    for (std::size_t p = 0; p < count; ++p) {
        if (is_fixed(p)) {
            v[p] = glm::dvec3{0.0};
            if (clamped && p == 0) x[0] = clamp->anchor_m;
            continue;
        }
        v[p] += glm::dvec3{scratch.rhs[3 * p], scratch.rhs[3 * p + 1], scratch.rhs[3 * p + 2]};
        x[p] += dt * v[p];
    }
    // The forces at the end of the step, as backward Euler has them: f(x + dx) = f(x) - H dx, with dx
    // the step's motion (zero for fixed points). This is the reaction a held (fixed) point feels: the
    // stem has already answered the hand's move within this step. One banded product, no second pass
    // over the springs.
    Band stiffness{scratch.stiffness, n};
    scratch.end_force.assign(count, glm::dvec3{0.0});
    auto moved = [&](std::size_t i) { return is_fixed(i / 3) ? 0.0 : dt * v[i / 3][static_cast<glm::length_t>(i % 3)]; };
    for (std::size_t i = 0; i < n; ++i) {
        const std::size_t j0 = i >= bandwidth ? i - bandwidth : 0;
        double change = 0.0;
        for (std::size_t j = j0; j <= i; ++j) change += stiffness.at(i, j) * moved(j);
        for (std::size_t j = i + 1; j < std::min(n, i + bandwidth + 1); ++j) change += stiffness.at(j, i) * moved(j);
        scratch.end_force[i / 3][static_cast<glm::length_t>(i % 3)] = f[i / 3][static_cast<glm::length_t>(i % 3)] - change;
    }
    return true;
}

} // namespace ikebana::systems::physics
