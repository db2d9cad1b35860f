#include "systems/physics/stem_dynamics.hpp"
#include "systems/physics/stem_frame.hpp"

#include <algorithm>
#include <cmath>
#include <array>
#include <cstring>

namespace ikebana::systems::physics {

using components::StemClamp;
using components::StemFrame;
using components::StemPoints;
using components::StemRestShape;
using components::StemSprings;

namespace {

// The system matrix's scalar bandwidth. A hinge couples P_{i-1} with P_{i+1} on the same axis only
// (its small-angle Hessian is k c c^T times the identity): 3 * 2 = 6 columns; a segment couples a point's
// three axes with its neighbour's: at most 3 + 2 = 5. Entries further out are always zero (the band was 8
// wide before: 40 % of the factorisation's work went to them).
constexpr std::size_t bandwidth = 6;

// Below this |e_i x e_i+1| the bend plane is undefined; the hinge is taken as straight.
constexpr double straight_sine = 1e-12;

struct Bend {
    double angle = 0.0;
    glm::dvec3 normal{0.0};
    bool has_plane = false;
};

// The library's atan2 out of line and out of the hinge loop's way (a hinge bent beyond 7 degrees is rare).
[[gnu::noinline, gnu::cold]] double library_angle(double s, double c) { return std::atan2(s, c); }

// atan2(s, c) for s >= 0. A stem's hinges are nearly straight (a 20-segment stem bent 45 degrees turns
// 2.25 degrees at each): for s <= c / 8 the series t - t^3/3 + ... - t^19/19 of t = s / c, whose first
// omitted term is under 5e-20 of the result; elsewhere the library's atan2, 5x as many instructions.
[[gnu::always_inline]] inline double angle_of(double s, double c) {
    if (!(c > 0.0 && s <= 0.125 * c)) [[unlikely]]
        return library_angle(s, c);
    const double t = s / c;
    const double u = t * t;
    // -1/3 + u/5 - ... - u^8/19 by Estrin's scheme: four short chains side by side, not Horner's nine
    // steps one after another (this was on every hinge's critical path).
    const double u2 = u * u;
    const double u4 = u2 * u2;
    const double q0 = -1.0 / 3.0 + u * (1.0 / 5.0);
    const double q1 = -1.0 / 7.0 + u * (1.0 / 9.0);
    const double q2 = -1.0 / 11.0 + u * (1.0 / 13.0);
    const double q3 = -1.0 / 15.0 + u * (1.0 / 17.0);
    const double p = (q0 + u2 * q1) + u4 * ((q2 + u2 * q3) + u4 * (-1.0 / 19.0));
    return t + t * u * p;
}

[[gnu::always_inline]] inline Bend bend_between(glm::dvec3 e_a, glm::dvec3 e_b) {
    const glm::dvec3 c = glm::cross(e_a, e_b);
    const double s = glm::length(c);
    Bend bend;
    bend.angle = angle_of(s, glm::dot(e_a, e_b));
    if (s > straight_sine) {
        bend.normal = c * (1.0 / s); // one division, not three
        bend.has_plane = true;
    }
    return bend;
}

bool clamp_active(const StemClamp* clamp) { return clamp != nullptr && clamp->engaged; }

// The rest bends have directions on the stem and the frame to read them in (stem_frame.hpp).
bool directed(const StemRestShape& rest, const StemFrame* frame) {
    return frame != nullptr && physics::bends_have_directions(rest, *frame) && frame->segment_direction.size() == frame->director.size();
}

// Hinge i's rest bend as a rotation vector in the room: its angle about its direction in the frame
// of the segment below it, that frame carried to where the segment points now (e_in). The frame is
// updated once a tick; carried here, the rest bend turns with its segment within every step. Read from
// the frame as it was, it lagged the segment's turn: a follower torque a step late, which fed a stiff
// branch's fastest mode until it tipped out of the pins (a cherry let go at 45 degrees).
glm::dvec3 rest_bend(const StemRestShape& rest, const StemFrame& frame, std::size_t i, glm::dvec3 e_in) {
    const glm::dvec3 was = frame.segment_direction[i - 1];
    const glm::dvec3 d1 = physics::transport(frame.director[i - 1], was, e_in);
    const glm::dvec2 dir = rest.hinge_bend_direction[i - 1];
    return rest.hinge_angle_rad[i - 1] * (dir.x * d1 + dir.y * glm::cross(e_in, d1));
}

// Lower band of a symmetric n x n matrix: row i holds columns i - bandwidth .. i. Rows and vectors are
// padded with `bandwidth` zero rows on each side (a padding row's diagonal is 1), so every loop below has
// a fixed length, with no bounds to test and no index arithmetic per entry: entries left of column 0 and
// padding rows are zeros, which add nothing. The padded layout is what the compiler unrolls.
constexpr std::size_t stride = bandwidth + 1;
constexpr std::size_t pad = bandwidth;

struct Band {
    double* data; // (n + 2 pad) rows of `stride`
    std::size_t n;
    [[nodiscard]] double* row(std::size_t i) const { return data + (i + pad) * stride; }
};

// Sizes a padded band or vector for n unknowns and writes its padding (zeros, a padding row's diagonal
// 1). One scratch serves stems of different lengths, so the size changes from stem to stem: the storage
// keeps its capacity and only the padding is written; the steps write every entry of rows 0..n-1.
void size_band(std::vector<double>& storage, std::size_t n) {
    storage.resize((n + 2 * pad) * stride);
    for (std::size_t r = 0; r < pad; ++r) {
        for (const std::size_t row : {r, n + pad + r}) {
            double* entries = storage.data() + row * stride;
            for (std::size_t d = 0; d < stride; ++d) entries[d] = d == bandwidth ? 1.0 : 0.0;
        }
    }
}
void size_vector(std::vector<double>& storage, std::size_t n, double padding) {
    storage.resize(n + 2 * pad);
    for (std::size_t r = 0; r < pad; ++r) storage[r] = storage[n + pad + r] = padding;
}

// y = A x for the symmetric A whose lower band `a` holds; x and y are padded (x[-pad..n+pad), zeros
// outside 0..n-1), y_i for i in 0..n-1 written.
void symmetric_product(const Band& a, const double* x, double* y) {
    for (std::size_t i = 0; i < a.n; ++i) {
        const double* r = a.row(i);
        const double* xr = x + i - bandwidth; // x at the row's first column
        double sum = 0.0;
#pragma GCC unroll 8
        for (std::size_t d = 0; d < stride; ++d) sum += r[d] * xr[d];
#pragma GCC unroll 8
        for (std::size_t t = 1; t <= bandwidth; ++t) sum += a.row(i + t)[bandwidth - t] * x[i + t];
        y[i] = sum;
    }
}

// In-place banded factorisation A = L D L^T (L unit lower, D diagonal; A symmetric positive definite,
// so every D > 0) and solve of A x = b; b is padded like the vectors above. Row i keeps L's entries left
// of the diagonal and D_i on it, and D's inverses are kept in `inverse` (padded too) so that the solves
// multiply. Not Cholesky's L L^T: a row waits for the one before it through a product and a division,
// without a square root between them (that root was most of the solve's time).
bool ldlt_solve(const Band& a, double* b, std::vector<double>& inverse_storage) {
    const std::size_t n = a.n;
    size_vector(inverse_storage, n, 1.0);
    double* inverse = inverse_storage.data() + pad;
    for (std::size_t i = 0; i < n; ++i) {
        double* ri = a.row(i);
        double w[bandwidth]; // L(i, k) D(k) for k = i - bandwidth + m
#pragma GCC unroll 8
        for (std::size_t d = 0; d < bandwidth; ++d) { // column j = i - bandwidth + d < i
            const double* rj = a.row(i + d - bandwidth);
            double sum = ri[d];
            // k = i - bandwidth + m for m < d: L(j, k) = rj[m + bandwidth - d]
#pragma GCC unroll 8
            for (std::size_t m = 0; m < d; ++m) sum -= w[m] * rj[m + bandwidth - d];
            w[d] = sum;
        }
        double diagonal = ri[bandwidth];
#pragma GCC unroll 8
        for (std::size_t m = 0; m < bandwidth; ++m) {
            ri[m] = w[m] * (inverse - bandwidth)[i + m]; // the padding's inverse (1) left of row 0
            diagonal -= w[m] * ri[m];
        }
        if (!(diagonal > 0.0)) return false;
        ri[bandwidth] = diagonal;
        inverse[i] = 1.0 / diagonal;
    }
    for (std::size_t i = 0; i < n; ++i) { // L y = b
        const double* ri = a.row(i);
        const double* yr = b + i - bandwidth;
        double sum = b[i];
#pragma GCC unroll 8
        for (std::size_t m = 0; m < bandwidth; ++m) sum -= ri[m] * yr[m];
        b[i] = sum;
    }
    for (std::size_t i = n; i-- > 0;) { // L^T x = D^-1 y
        double sum = b[i] * inverse[i];
#pragma GCC unroll 8
        for (std::size_t t = 1; t <= bandwidth; ++t) sum -= a.row(i + t)[bandwidth - t] * b[i + t];
        b[i] = sum;
    }
    return true;
}

} // namespace

double hinge_angle(const StemPoints& points, std::size_t i) {
    const auto& x = points.position_m;
    return bend_between(glm::normalize(x[i] - x[i - 1]), glm::normalize(x[i + 1] - x[i])).angle;
}

namespace {

// Each segment's length and direction, computed once a step for the forces and the Hessian alike.
void measure_segments(const StemPoints& points, std::vector<StemSegment>& segments) {
    const auto& x = points.position_m;
    const std::size_t count = x.size();
    segments.resize(count > 0 ? count - 1 : 0);
    for (std::size_t i = 1; i < count; ++i) {
        const glm::dvec3 d = x[i] - x[i - 1];
        const double length = glm::length(d);
        segments[i - 1] = {length > 0.0 ? d * (1.0 / length) : glm::dvec3{0.0}, length}; // one division, not three
    }
}

void forces_of(const StemPoints& points, const std::vector<StemSegment>& segments, const StemRestShape& rest,
               const StemSprings& springs, const StemClamp* clamp, const StemFrame* frame, glm::dvec3 gravity,
               std::vector<glm::dvec3>& f) {
    const std::size_t count = points.position_m.size();
    f.resize(count);
    for (std::size_t p = 0; p < count; ++p) f[p] = points.mass_kg[p] * gravity + points.external_force_n[p];

    // Eq. 1: structure springs.
    for (std::size_t i = 1; i < count; ++i) {
        const StemSegment& s = segments[i - 1];
        if (s.length_m <= 0.0) continue;
        const glm::dvec3 spring = springs.axial_n_per_m[i - 1] * (s.length_m - rest.segment_length_m[i - 1]) * s.direction;
        f[i - 1] += spring;
        f[i] -= spring;
    }
    // Eq. 2-3: hinge springs at P1..Pn-1, with the coupling force on P_i.
    const bool with_directions = directed(rest, frame);
    for (std::size_t i = 1; i + 1 < count; ++i) {
        const double l_in = segments[i - 1].length_m;
        const double l_out = segments[i].length_m;
        if (l_in <= 0.0 || l_out <= 0.0) continue;
        const glm::dvec3 e_in = segments[i - 1].direction;
        const glm::dvec3 e_out = segments[i].direction;
        const Bend bend = bend_between(e_in, e_out);
        if (with_directions && physics::hinge_has_direction(rest, i)) {
            // Eq. 3 with the bend as a vector: the torque k (b0 - b) turns the upper segment toward its
            // rest bend b0, wherever about the stem that lies, and the lower one the other way. A torque T
            // on a segment of direction e and length l is the force T x e / l at its far end (its part
            // along e, twist, goes to the frame). With b0 in the bend's plane this is the scalar form below.
            const glm::dvec3 now = bend.has_plane ? bend.angle * bend.normal : glm::dvec3{0.0};
            const glm::dvec3 torque = (rest_bend(rest, *frame, i, e_in) - now) * springs.hinge_nm_per_rad[i - 1];
            const glm::dvec3 f_prev = glm::cross(torque, e_in) * (1.0 / l_in);
            const glm::dvec3 f_next = glm::cross(torque, e_out) * (1.0 / l_out);
            f[i - 1] += f_prev;
            f[i + 1] += f_next;
            f[i] -= f_prev + f_next;
            continue;
        }
        if (!bend.has_plane) continue; // straight: zero torque at theta0 = 0, undefined plane otherwise
        double torque = springs.hinge_nm_per_rad[i - 1] * (bend.angle - rest.hinge_angle_rad[i - 1]);
        // A naturally bent hinge (a branch's curve) pulled nearly straight: its plane, the direction of
        // the torque, turns arbitrarily as the angle goes to zero, while the torque toward the rest bend
        // stays large. Pushed in a new direction each step, the stem gained energy until it flew (a
        // cherry branch held at 45 degrees with its curve down). Below half its rest angle the torque
        // fades with the angle, to none when straight, where the plane is undefined.
        const double rest_angle = rest.hinge_angle_rad[i - 1];
        if (rest_angle > 0.0 && bend.angle < 0.5 * rest_angle) torque *= bend.angle / (0.5 * rest_angle);
        // (Divisions are the hinge's slowest operations: one per scalar, not one per component.)
        const glm::dvec3 f_prev = glm::cross(bend.normal, -e_in) * (torque / l_in);
        const glm::dvec3 f_next = glm::cross(bend.normal, e_out) * (-torque / l_out);
        f[i - 1] += f_prev;
        f[i + 1] += f_next;
        f[i] -= f_prev + f_next;
    }
    // The clamp's root hinge works like Eq. 3 with the clamp direction in place of e_i.
    if (clamp_active(clamp) && count >= 2 && segments[0].length_m > 0.0) {
        const glm::dvec3 e = segments[0].direction;
        const double l = segments[0].length_m;
        const Bend bend = bend_between(clamp->direction, e);
        if (bend.has_plane) {
            const glm::dvec3 f_next = glm::cross(bend.normal, e) * (-clamp->hinge_nm_per_rad * bend.angle / l);
            f[1] += f_next;
            f[0] -= f_next;
        }
    }
}

} // namespace

void stem_forces(const StemPoints& points, const StemRestShape& rest, const StemSprings& springs,
                 const StemClamp* clamp, glm::dvec3 gravity, std::vector<glm::dvec3>& f, const StemFrame* frame) {
    std::vector<StemSegment> segments;
    stem_forces(points, rest, springs, clamp, gravity, f, segments, frame);
}

void stem_forces(const StemPoints& points, const StemRestShape& rest, const StemSprings& springs,
                 const StemClamp* clamp, glm::dvec3 gravity, std::vector<glm::dvec3>& f, std::vector<StemSegment>& segments,
                 const StemFrame* frame) {
    measure_segments(points, segments);
    forces_of(points, segments, rest, springs, clamp, frame, gravity, f);
}

StemEnergy stem_energy(const StemPoints& points, const StemRestShape& rest, const StemSprings& springs,
                       const StemClamp* clamp, glm::dvec3 gravity, const StemFrame* frame) {
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
    const bool with_directions = directed(rest, frame);
    for (std::size_t i = 1; i + 1 < x.size(); ++i) {
        if (with_directions && physics::hinge_has_direction(rest, i)) {
            const glm::dvec3 e_in = glm::normalize(x[i] - x[i - 1]);
            const Bend bend = bend_between(e_in, glm::normalize(x[i + 1] - x[i]));
            const glm::dvec3 gap = (bend.has_plane ? bend.angle * bend.normal : glm::dvec3{0.0}) - rest_bend(rest, *frame, i, e_in);
            energy.elastic_j += 0.5 * springs.hinge_nm_per_rad[i - 1] * glm::dot(gap, gap);
            continue;
        }
        const double dtheta = hinge_angle(points, i) - rest.hinge_angle_rad[i - 1];
        energy.elastic_j += 0.5 * springs.hinge_nm_per_rad[i - 1] * dtheta * dtheta;
    }
    if (clamp_active(clamp) && x.size() >= 2) {
        const double theta = bend_between(clamp->direction, glm::normalize(x[1] - x[0])).angle;
        energy.elastic_j += 0.5 * clamp->hinge_nm_per_rad * theta * theta;
    }
    return energy;
}

void reserve_scratch(StemSolverScratch& s, std::size_t points) {
    const std::size_t n = 3 * points;
    for (auto* band : {&s.band, &s.stiffness}) band->reserve((n + 2 * pad) * stride);
    for (auto* vector : {&s.rhs, &s.motion, &s.inverse_diagonal}) vector->reserve(n + 2 * pad);
    s.segment_block.reserve(6 * points);
    s.bend_coupling.reserve(3 * points);
    s.segments.reserve(points);
    s.force.reserve(points);
    s.end_force.reserve(points);
}

std::size_t tick_parts(double dt) {
    const double parts = std::ceil(dt / max_part_s - 1e-9); // 1 ms is one part, not two by rounding
    if (!std::isfinite(parts) || parts <= 1.0) return 1;
    return static_cast<std::size_t>(std::min(parts, static_cast<double>(max_substeps)));
}

namespace {

bool is_fixed(const StemPoints& points, const StemClamp* clamp, std::size_t p) { return points.pinned[p] != 0 || (clamp_active(clamp) && p == 0); }

// The step up to its linear system: forces, H (kept in scratch.stiffness), the system matrix A
// (scratch.band) and the right-hand side M v + h f (scratch.rhs), fixed points as identity rows.
//
// A and the right-hand side go where `a` says: the stem's own scratch, or one lane of four stems'
// interleaved system (an entry every `lanes` doubles), so that the lanes' solve needs no copy.
struct SystemAt {
    double* band;    // padded row 0's first entry
    double* rhs;     // padded entry 0
    std::size_t lanes = 1;
    [[nodiscard]] double* row(std::size_t i) const { return band + (i + pad) * stride * lanes; }
    [[nodiscard]] double& b(std::size_t i) const { return rhs[(i + pad) * lanes]; }
};

void assemble_step(const StemPoints& points, const StemRestShape& rest, const StemSprings& springs, const StemClamp* clamp,
                   const StemFrame* frame, glm::dvec3 gravity, double dt, StemSolverScratch& scratch, const SystemAt& a,
                   std::span<const SegmentSupport> supports) {
    const auto& v = points.velocity_m_s;
    const std::size_t count = points.position_m.size();
    const std::size_t n = 3 * count;
    const bool clamped = clamp_active(clamp);

    measure_segments(points, scratch.segments);
    forces_of(points, scratch.segments, rest, springs, clamp, frame, gravity, scratch.force);
    const auto& f = scratch.force;

    // H: positive semi-definite approximation of the energy Hessian, banded. Each segment's block
    // k (e e^T + t (I - e e^T)) sits on both its points' diagonals and, negated, between them; each hinge's
    // small-angle Hessian k c c^T (c: the bend's weights on its three points) acts on every axis alike, so
    // it is three scalars a point: with itself, with the point below, with the one below that.
    scratch.segment_block.resize(6 * (count > 0 ? count - 1 : 0));
    for (std::size_t i = 1; i < count; ++i) {
        double* block = &scratch.segment_block[6 * (i - 1)]; // xx xy xz yy yz zz
        const double length = scratch.segments[i - 1].length_m;
        if (length <= 0.0) {
            std::fill_n(block, 6, 0.0);
            continue;
        }
        const glm::dvec3 e = scratch.segments[i - 1].direction;
        const double k = springs.axial_n_per_m[i - 1];
        const double transverse = std::max(0.0, 1.0 - rest.segment_length_m[i - 1] / length);
        const double along = k * (1.0 - transverse);
        const double across = k * transverse;
        block[0] = along * e.x * e.x + across;
        block[1] = along * e.x * e.y;
        block[2] = along * e.x * e.z;
        block[3] = along * e.y * e.y + across;
        block[4] = along * e.y * e.z;
        block[5] = along * e.z * e.z + across;
    }
    scratch.bend_coupling.assign(3 * count, 0.0); // per point: with itself, with p-1, with p-2
    double* bend = scratch.bend_coupling.data();
    for (std::size_t i = 1; i + 1 < count; ++i) {
        const double k = springs.hinge_nm_per_rad[i - 1];
        const double c0 = 1.0 / rest.segment_length_m[i - 1];
        const double c2 = 1.0 / rest.segment_length_m[i];
        const double c1 = -(c0 + c2);
        bend[3 * (i - 1)] += k * c0 * c0;
        bend[3 * i] += k * c1 * c1;
        bend[3 * (i + 1)] += k * c2 * c2;
        bend[3 * i + 1] += k * c1 * c0;
        bend[3 * (i + 1) + 1] += k * c2 * c1;
        bend[3 * (i + 1) + 2] += k * c2 * c0;
    }
    if (clamped && count >= 2) {
        const double c = 1.0 / rest.segment_length_m[0];
        const double k = clamp->hinge_nm_per_rad;
        bend[0] += k * c * c;
        bend[3] += k * c * c;
        bend[3 + 1] -= k * c * c;
    }
    // H and the system matrix A = M (1 + h alpha) + (h beta + h^2) H side by side (H is kept for the
    // end-of-step forces), every entry written once. Row 3p + r holds columns 3p + r - 6 .. 3p + r:
    // point p-2's axes r..2, all of p-1's, p's axes 0..r. A missing segment reads as a zero block.
    const double beta = springs.stiffness_damping_s;
    const double alpha = springs.air_drag_per_s;
    const double stiffness_scale = dt * beta + dt * dt;
    if (scratch.want_end_force) size_band(scratch.stiffness, n);
    const Band h{scratch.stiffness.data(), n};
    static constexpr double no_segment[6] = {};
    for (std::size_t p = 0; p < count; ++p) {
        const double* lo = p >= 1 ? &scratch.segment_block[6 * (p - 1)] : no_segment; // xx xy xz yy yz zz
        const double* up = p + 1 < count ? &scratch.segment_block[6 * p] : no_segment;
        const double b0 = bend[3 * p];
        const double b1 = bend[3 * p + 1];
        const double b2 = bend[3 * p + 2];
        const double rows[3][stride] = {
            {b2, 0.0, 0.0, b1 - lo[0], -lo[1], -lo[2], lo[0] + up[0] + b0},
            {b2, 0.0, -lo[1], b1 - lo[3], -lo[4], lo[1] + up[1], lo[3] + up[3] + b0},
            {b2, -lo[2], -lo[4], b1 - lo[5], lo[2] + up[2], lo[4] + up[4], lo[5] + up[5] + b0},
        };
        const double mass = points.mass_kg[p] * (1.0 + dt * alpha);
        for (std::size_t r = 0; r < 3; ++r) {
            double* ar = a.row(3 * p + r);
#pragma GCC unroll 8
            for (std::size_t d = 0; d < stride; ++d) ar[d * a.lanes] = rows[r][d] * stiffness_scale;
            ar[bandwidth * a.lanes] += mass;
            if (!scratch.want_end_force) continue; // H itself is only for the end forces
            double* hr = h.row(3 * p + r);
#pragma GCC unroll 8
            for (std::size_t d = 0; d < stride; ++d) hr[d] = rows[r][d];
        }
    }

    // Backward Euler's change dv solves A dv = h (f - (beta + h) H v - alpha M v). Added to A v on both
    // sides the H terms cancel (A's own is (h beta + h^2) H v), leaving A v' = M v + h f for the new
    // velocity v' = v + dv: no product with H, the same solution.
    for (std::size_t p = 0; p < count; ++p) {
        const glm::dvec3 momentum = points.mass_kg[p] * v[p] + dt * f[p];
        for (std::size_t r = 0; r < 3; ++r) a.b(3 * p + r) = momentum[static_cast<glm::length_t>(r)];
    }
    // What it lies across: the spring k on the supported point's height g below top (g > 0), with damping
    // c, implicit: (h^2 k + h c) w w^T on the two ends' z (w = (1 - t, t)) and h k g w on their right-hand
    // side. Row 3p + 2 holds p's z on its diagonal (entry `bandwidth`) and p-1's z three columns left.
    for (const SegmentSupport& support : supports) {
        const std::size_t lower = support.segment;
        if (lower + 1 >= count) continue;
        const double wa = 1.0 - support.t, wb = support.t;
        const double below = std::min(support.top_m - (wa * points.position_m[lower].z + wb * points.position_m[lower + 1].z), segment_support_exit_m_s * dt);
        if (below <= 0.0) continue;
        const double s = dt * dt * segment_support_n_per_m + dt * segment_support_n_s_per_m;
        a.row(3 * lower + 2)[bandwidth * a.lanes] += s * wa * wa;
        a.row(3 * lower + 5)[bandwidth * a.lanes] += s * wb * wb;
        a.row(3 * lower + 5)[(bandwidth - 3) * a.lanes] += s * wa * wb;
        a.b(3 * lower + 2) += dt * segment_support_n_per_m * below * wa;
        a.b(3 * lower + 5) += dt * segment_support_n_per_m * below * wb;
    }
    // A fixed point keeps v' = 0 in the solve; a held one moving with the hand (the grab sets its
    // velocity) still drags its neighbours: its column's A v goes to the right-hand side first
    // (-(h beta + h^2) H_ij v_j for the rows it couples to), as the change-of-velocity form had it. All
    // columns are read before any is cleared.
    for (std::size_t p = 0; p < count; ++p) {
        if (!is_fixed(points, clamp, p) || v[p] == glm::dvec3{0.0}) continue;
        for (std::size_t r = 0; r < 3; ++r) {
            const std::size_t j = 3 * p + r;
            const double vj = v[p][static_cast<glm::length_t>(r)];
            const double* row = a.row(j);
            for (std::size_t d = 0; d < bandwidth; ++d) {
                if (j + d >= bandwidth) a.b(j + d - bandwidth) -= row[d * a.lanes] * vj; // rows above: A(j, k) = A(k, j)
            }
            for (std::size_t t = 1; t <= bandwidth && j + t < n; ++t) a.b(j + t) -= a.row(j + t)[(bandwidth - t) * a.lanes] * vj;
        }
    }
    for (std::size_t p = 0; p < count; ++p) {
        if (!is_fixed(points, clamp, p)) continue;
        for (std::size_t r = 0; r < 3; ++r) {
            const std::size_t i = 3 * p + r;
            double* row = a.row(i);
            for (std::size_t d = 0; d < bandwidth; ++d) row[d * a.lanes] = 0.0;
            for (std::size_t t = 1; t <= bandwidth; ++t) a.row(i + t)[(bandwidth - t) * a.lanes] = 0.0;
            row[bandwidth * a.lanes] = 1.0;
            a.b(i) = 0.0; // v' = 0
        }
    }
}

// The step from its solved system (the new velocities in scratch.rhs) on: positions, and the forces at
// the end of the step. False for a non-finite solution.
bool finish_step(StemPoints& points, const StemClamp* clamp, double dt, StemSolverScratch& scratch, const SystemAt& solved) {
    auto& x = points.position_m;
    auto& v = points.velocity_m_s;
    const std::size_t count = x.size();
    const std::size_t n = 3 * count;
    const bool clamped = clamp_active(clamp);
    const auto& f = scratch.force;
    const Band h{scratch.stiffness.data(), n};
    for (std::size_t i = 0; i < n; ++i) {
        if (!std::isfinite(solved.b(i))) return false;
    }
    // The step's motion dx: h v'. A held point's v' is 0 in the solve, but the solve took it as moving
    // with the hand (its velocity's column went to the right-hand side) and the grab puts it there: its
    // dx is h times the velocity it came with. Left at zero, the end forces below had the held point
    // stay while its neighbours went on with the hand: a chrysanthemum (18 g) lifted at 5 cm/s by a
    // grip on two points pulled 2.6 N on the hand, 9.7 N once its curve had a direction.
    const bool end_forces = scratch.want_end_force;
    double* moved = nullptr;
    if (end_forces) {
        size_vector(scratch.motion, n, 0.0);
        moved = scratch.motion.data() + pad;
    }
    for (std::size_t p = 0; p < count; ++p) {
        if (is_fixed(points, clamp, p)) {
            if (end_forces) { // the clamp's anchor stays (every entry written: the buffer is a scratch)
                for (std::size_t r = 0; r < 3; ++r) moved[3 * p + r] = clamped && p == 0 ? 0.0 : dt * v[p][static_cast<glm::length_t>(r)];
            }
            v[p] = glm::dvec3{0.0};
            if (clamped && p == 0) x[0] = clamp->anchor_m;
            continue;
        }
        v[p] = glm::dvec3{solved.b(3 * p), solved.b(3 * p + 1), solved.b(3 * p + 2)};
        x[p] += dt * v[p];
        if (end_forces) {
            for (std::size_t r = 0; r < 3; ++r) moved[3 * p + r] = dt * v[p][static_cast<glm::length_t>(r)];
        }
    }
    // The forces at the end of the step, as backward Euler has them: f(x + dx) = f(x) - H dx. This is
    // the reaction a held (fixed) point feels: the stem has already answered the hand's move within this
    // step. One banded product, no second pass over the springs.
    if (!end_forces) {
        scratch.end_force = f;
        return true;
    }
    size_vector(scratch.rhs, n, 0.0);
    double* change = scratch.rhs.data() + pad; // (where a lone stem's solution was: it is spent)
    symmetric_product(h, moved, change);
    scratch.end_force.resize(count);
    for (std::size_t p = 0; p < count; ++p) {
        scratch.end_force[p] = f[p] - glm::dvec3{change[3 * p], change[3 * p + 1], change[3 * p + 2]};
    }
    return true;
}

// Four stems' systems solved side by side, one in each lane of a vector of four doubles: each lane
// does exactly the operations ldlt_solve does on its stem, in the same order (no fused
// multiply-add: none is enabled), so its results are the same bit for bit; a 256-bit machine does four
// stems' work in the instructions of one. Each stem assembles its system straight into its lane
// (entry by entry, lane by lane); a shorter system is continued by identity rows. `ok[l]`: lane l was
// positive definite.
constexpr std::size_t lanes = 4;
static_assert(std::tuple_size_v<decltype(LaneScratch::Group::own)> == lanes);
using Lanes = double __attribute__((vector_size(8 * lanes)));
// The same at any double's address, aliasing doubles: the interleaved arrays are read through it.
using LanesAt = double __attribute__((vector_size(8 * lanes), aligned(8), may_alias));

// Not under ThreadSanitizer: the clones' resolver runs while the program is being loaded, before TSan
// is set up, and TSan's instrumentation of it crashed every TSan binary at start.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(__SANITIZE_THREAD__)
__attribute__((target_clones("avx2", "default")))
#endif
void ldlt_solve_lanes(double* a, double* b, double* inverse, std::size_t n, bool* ok) {
    // a: (n + 2 pad) rows of `stride` entries of `lanes`; b, inverse: (n + 2 pad) of `lanes`. Read and
    // written in place through LanesAt references (no helper functions: one taking or returning a
    // 256-bit vector has a different ABI in each clone).
    const auto at = [](double* p) -> LanesAt& { return *reinterpret_cast<LanesAt*>(p); };
    const auto row = [&](std::size_t i) { return a + (i + pad) * stride * lanes; };
    const Lanes one = Lanes{} + 1.0;
    for (std::size_t i = 0; i < n; ++i) {
        double* ri = row(i);
        Lanes w[bandwidth];
        for (std::size_t d = 0; d < bandwidth; ++d) {
            double* rj = row(i + d - bandwidth);
            Lanes sum = at(ri + d * lanes);
            for (std::size_t m = 0; m < d; ++m) sum -= w[m] * at(rj + (m + bandwidth - d) * lanes);
            w[d] = sum;
        }
        Lanes diagonal = at(ri + bandwidth * lanes);
        for (std::size_t m = 0; m < bandwidth; ++m) {
            const Lanes l = w[m] * at(inverse + (i + pad + m - bandwidth) * lanes);
            at(ri + m * lanes) = l;
            diagonal -= w[m] * l;
        }
        // A lane whose stem is not positive definite is refused with 1 in its place, and the others go
        // on: one compare and a rarely taken branch.
        const auto positive = diagonal > 0.0;
        bool all_positive = true;
        for (std::size_t l = 0; l < lanes; ++l) all_positive = all_positive && positive[l] != 0;
        if (!all_positive) {
            for (std::size_t l = 0; l < lanes; ++l) {
                if (!positive[l]) {
                    ok[l] = false;
                    diagonal[l] = 1.0;
                }
            }
        }
        at(ri + bandwidth * lanes) = diagonal;
        at(inverse + (i + pad) * lanes) = one / diagonal;
    }
    for (std::size_t i = 0; i < n; ++i) { // L y = b
        double* ri = row(i);
        Lanes sum = at(b + (i + pad) * lanes);
        for (std::size_t m = 0; m < bandwidth; ++m) sum -= at(ri + m * lanes) * at(b + (i + pad + m - bandwidth) * lanes);
        at(b + (i + pad) * lanes) = sum;
    }
    for (std::size_t i = n; i-- > 0;) { // L^T x = D^-1 y
        Lanes sum = at(b + (i + pad) * lanes) * at(inverse + (i + pad) * lanes);
        for (std::size_t t = 1; t <= bandwidth; ++t) sum -= at(row(i + t) + (bandwidth - t) * lanes) * at(b + (i + pad + t) * lanes);
        at(b + (i + pad) * lanes) = sum;
    }
}

} // namespace

bool step_stem(StemPoints& points, const StemRestShape& rest, const StemSprings& springs, const StemClamp* clamp,
               glm::dvec3 gravity, double dt, StemSolverScratch& scratch, const StemFrame* frame, std::span<const SegmentSupport> supports) {
    const std::size_t n = 3 * points.position_m.size();
    size_band(scratch.band, n);
    size_vector(scratch.rhs, n, 0.0);
    const SystemAt own{scratch.band.data(), scratch.rhs.data(), 1};
    assemble_step(points, rest, springs, clamp, frame, gravity, dt, scratch, own, supports);
    if (!ldlt_solve(Band{scratch.band.data(), n}, scratch.rhs.data() + pad, scratch.inverse_diagonal)) return false;
    return finish_step(points, clamp, dt, scratch, own);
}

void reserve_scratch(LaneScratch& s, const std::vector<std::size_t>& points_longest_first) {
    // Stems are grouped four at a time longest first (step_stems' callers sort them): a group's size is
    // its first stem's.
    const std::size_t groups = (points_longest_first.size() + lanes - 1) / lanes;
    if (s.groups.size() < groups) s.groups.resize(groups);
    for (std::size_t k = 0; k < groups; ++k) {
        const std::size_t n = 3 * points_longest_first[k * lanes];
        auto& g = s.groups[k];
        g.band.reserve((n + 2 * pad) * stride * lanes);
        g.rhs.reserve((n + 2 * pad) * lanes);
        g.inverse_diagonal.reserve((n + 2 * pad) * lanes);
    }
}

void step_stems(std::span<const StemStep> stems, glm::dvec3 gravity, LaneScratch& lane_scratch, std::span<std::uint8_t> ok) {
    for (std::size_t first = 0; first < stems.size(); first += lanes) {
        const std::size_t group = std::min(lanes, stems.size() - first);
        if (group == 1) { // nothing to share a register with
            const auto& s = stems[first];
            ok[first] = step_stem(*s.points, *s.rest, *s.springs, s.clamp, gravity, s.dt_s, *s.scratch, s.frame, s.supports) ? 1 : 0;
            continue;
        }
        std::size_t n = 0;
        std::array<std::size_t, lanes> own{};
        for (std::size_t l = 0; l < group; ++l) {
            own[l] = 3 * stems[first + l].points->position_m.size();
            n = std::max(n, own[l]);
        }
        // Each stem writes its own lane (every entry of its rows); the rest is identity rows past a
        // shorter stem's end and in empty lanes, and the padding, which the solve leaves as they are:
        // written when the group's shape changes, not every step.
        const std::size_t group_index = first / lanes;
        if (lane_scratch.groups.size() <= group_index) lane_scratch.groups.resize(group_index + 1);
        auto& g = lane_scratch.groups[group_index];
        auto& a = g.band;
        auto& b = g.rhs;
        auto& inverse = g.inverse_diagonal;
        if (g.n != n || g.own != own) {
            g.n = n;
            g.own = own;
            a.assign((n + 2 * pad) * stride * lanes, 0.0);
            b.assign((n + 2 * pad) * lanes, 0.0);
            inverse.assign((n + 2 * pad) * lanes, 1.0);
            for (std::size_t l = 0; l < lanes; ++l) {
                for (std::size_t i = 0; i < n + 2 * pad; ++i) {
                    if (i < pad || i >= pad + own[l]) a[(i * stride + bandwidth) * lanes + l] = 1.0;
                }
            }
        }
        for (std::size_t l = 0; l < group; ++l) {
            const auto& s = stems[first + l];
            assemble_step(*s.points, *s.rest, *s.springs, s.clamp, s.frame, gravity, s.dt_s, *s.scratch, SystemAt{a.data() + l, b.data() + l, lanes}, s.supports);
        }
        bool lane_ok[lanes] = {true, true, true, true};
        ldlt_solve_lanes(a.data(), b.data(), inverse.data(), n, lane_ok);
        for (std::size_t l = 0; l < group; ++l) {
            const auto& s = stems[first + l];
            ok[first + l] = lane_ok[l] && finish_step(*s.points, s.clamp, s.dt_s, *s.scratch, SystemAt{a.data() + l, b.data() + l, lanes}) ? 1 : 0;
            // A failed lane may have carried NaN into its identity rows (0 * NaN): rebuilt next step.
            if (!ok[first + l]) g.n = 0;
        }
    }
}

} // namespace ikebana::systems::physics
