#include "systems/physics/stem_tree.hpp"

#include <algorithm>
#include <cmath>

#include "systems/physics/stem_frame.hpp"

namespace ikebana::systems::physics {

using components::StemPoints;

namespace {

bool clamped(const TreeChain& c) { return c.clamp != nullptr && c.clamp->engaged && c.parent < 0; }

// Any unit vector across `e` (a fork on a stem without a frame still needs a side to leave on).
glm::dvec3 across(glm::dvec3 e) {
    const glm::dvec3 helper = std::abs(e.x) < 0.9 ? glm::dvec3{1, 0, 0} : glm::dvec3{0, 1, 0};
    return glm::normalize(glm::cross(glm::cross(e, helper), e));
}

// The bend from e_a to e_b as a rotation vector (zero when straight).
glm::dvec3 bend_of(glm::dvec3 e_a, glm::dvec3 e_b) {
    const glm::dvec3 c = glm::cross(e_a, e_b);
    const double s = glm::length(c);
    if (s <= 1e-12) return glm::dvec3{0.0};
    return std::atan2(s, glm::dot(e_a, e_b)) / s * c;
}

struct RootHinge {
    std::uint32_t below, at, above; // the parent's point at - 1, the shared point, the twig's P1
    glm::dvec3 f_below{0.0}, f_above{0.0};
    double energy_j = 0.0;
    // What turning the parent's frame at the fork (its director about its segment) does to the hinge's
    // energy: dE/dphi and, Gauss-Newton, d2E/dphi2 (the fork's side is in that frame).
    double frame_gradient_nm = 0.0;
    double frame_stiffness_nm = 0.0;
};

// The root hinge of twig c: the directed hinge of stem_dynamics between the parent's segment into the
// shared point and the twig's first segment, toward the fork's rest bend. Its forces on the parent's
// point below and the twig's P1 (the shared point takes minus their sum).
RootHinge root_hinge(std::span<const TreeChain> chains, std::size_t c) {
    const TreeChain& twig = chains[c];
    const TreeChain& parent = chains[static_cast<std::size_t>(twig.parent)];
    const auto& xp = parent.points->position_m;
    const auto& xt = twig.points->position_m;
    const std::uint32_t k = twig.fork->at_point;
    RootHinge h{k - 1, k, 1};
    const glm::dvec3 d_in = xp[k] - xp[k - 1];
    const glm::dvec3 d_out = xt[1] - xt[0];
    const double l_in = glm::length(d_in), l_out = glm::length(d_out);
    if (l_in <= 0.0 || l_out <= 0.0) return h;
    const glm::dvec3 e_in = d_in / l_in, e_out = d_out / l_out;
    const glm::dvec3 rest = fork_rest_bend(twig, parent, e_in);
    const glm::dvec3 gap = rest - bend_of(e_in, e_out);
    const double stiffness = twig.fork->hinge_nm_per_rad;
    const glm::dvec3 torque = stiffness * gap;
    h.f_below = glm::cross(torque, e_in) / l_in;
    h.f_above = glm::cross(torque, e_out) / l_out;
    h.energy_j = 0.5 * stiffness * glm::dot(gap, gap);
    // Turning the parent's frame by phi turns the rest bend about e_in: d(rest)/dphi = e_in x rest. Points
    // cannot take a moment about the parent's own axis; its frame can (stem_frame's update).
    h.frame_gradient_nm = stiffness * glm::dot(gap, glm::cross(e_in, rest));
    h.frame_stiffness_nm = stiffness * glm::dot(rest, rest);
    return h;
}

bool valid_fork(std::span<const TreeChain> chains, std::size_t c) {
    const TreeChain& t = chains[c];
    if (t.parent < 0) return false;
    const auto p = static_cast<std::size_t>(t.parent);
    return p < c && t.fork != nullptr && t.fork->at_point >= 1 && t.fork->at_point < chains[p].points->position_m.size() &&
           t.points->position_m.size() >= 2;
}

// Numbers the tree's points: the root chain's in order, then each twig's from its P1 (its P0 is its
// parent's point). Every node's parent has a smaller number: eliminated from the last node down, each
// goes before its parent and its parent's parent, the only nodes it couples to that remain.
// Per-chain lists only grow: one shrunk for a smaller tree would free its chains' memory, which a larger
// tree (a branch pruned off, solved in this scratch next) would then allocate again on the 1 kHz lane.
template <typename T>
void grow_to(std::vector<T>& per_chain, std::size_t chains) {
    if (per_chain.size() < chains) per_chain.resize(chains);
}

void number_nodes(std::span<const TreeChain> chains, TreeScratch& s) {
    // The same tree as last step (the usual case): the same numbering.
    std::size_t at = 0;
    bool same = s.topology.size() == 3 * chains.size();
    for (const auto& chain : chains) {
        const std::int64_t size = static_cast<std::int64_t>(chain.points->position_m.size());
        const std::int64_t fork = chain.fork ? static_cast<std::int64_t>(chain.fork->at_point) : -1;
        for (const std::int64_t v : {size, static_cast<std::int64_t>(chain.parent), fork}) {
            same = same && s.topology[at] == v;
            if (at >= s.topology.size()) s.topology.push_back(v);
            else s.topology[at] = v;
            ++at;
        }
    }
    s.topology.resize(at);
    if (same) return;
    grow_to(s.node_of, chains.size());
    s.parent_node.clear();
    for (std::size_t c = 0; c < chains.size(); ++c) {
        const std::size_t count = chains[c].points->position_m.size();
        auto& nodes = s.node_of[c];
        nodes.resize(count);
        const bool twig = c > 0;
        for (std::size_t j = 0; j < count; ++j) {
            if (twig && j == 0) {
                nodes[0] = s.node_of[static_cast<std::size_t>(chains[c].parent)][chains[c].fork->at_point];
                continue;
            }
            nodes[j] = static_cast<std::uint32_t>(s.parent_node.size());
            s.parent_node.push_back(j == 0 ? -1 : static_cast<std::int32_t>(nodes[j - 1]));
        }
    }
}

using Sym3 = std::array<double, 6>;   // xx xy xz yy yz zz
using Block3 = std::array<double, 9>; // row-major

void add_scalar(Sym3& m, double v) {
    m[0] += v;
    m[3] += v;
    m[5] += v;
}
void add_scalar(Block3& m, double v) {
    m[0] += v;
    m[4] += v;
    m[8] += v;
}
glm::dvec3 times(const Sym3& m, glm::dvec3 v) {
    return {m[0] * v.x + m[1] * v.y + m[2] * v.z, m[1] * v.x + m[3] * v.y + m[4] * v.z, m[2] * v.x + m[4] * v.y + m[5] * v.z};
}
glm::dvec3 times(const Block3& m, glm::dvec3 v) {
    return {m[0] * v.x + m[1] * v.y + m[2] * v.z, m[3] * v.x + m[4] * v.y + m[5] * v.z, m[6] * v.x + m[7] * v.y + m[8] * v.z};
}
glm::dvec3 transposed_times(const Block3& m, glm::dvec3 v) {
    return {m[0] * v.x + m[3] * v.y + m[6] * v.z, m[1] * v.x + m[4] * v.y + m[7] * v.z, m[2] * v.x + m[5] * v.y + m[8] * v.z};
}

// Sylvester's test and the inverse of a symmetric 3x3 block, by its cofactors (symmetric too).
bool invert_positive(const Sym3& m, Sym3& out) {
    const double a = m[0], b = m[1], c = m[2], d = m[3], e = m[4], f = m[5];
    const double ca = d * f - e * e, cb = c * e - b * f, cc = b * e - c * d;
    const double cd = a * f - c * c, ce = b * c - a * e, cf = a * d - b * b;
    const double det = a * ca + b * cb + c * cc;
    if (!(a > 0.0 && cf > 0.0 && det > 0.0)) return false;
    const double r = 1.0 / det;
    out = {ca * r, cb * r, cc * r, cd * r, ce * r, cf * r};
    return true;
}

} // namespace

glm::dvec3 fork_rest_bend(const TreeChain& twig, const TreeChain& parent, glm::dvec3 e_in) {
    const std::uint32_t segment = twig.fork->at_point - 1;
    glm::dvec3 d1;
    const auto* frame = parent.frame;
    if (frame && segment < frame->director.size() && segment < frame->segment_direction.size()) {
        d1 = transport(frame->director[segment], frame->segment_direction[segment], e_in);
    } else {
        d1 = across(e_in);
    }
    const glm::dvec2 dir = twig.fork->direction;
    return twig.fork->angle_rad * (dir.x * d1 + dir.y * glm::cross(e_in, d1));
}

void reserve_scratch(TreeScratch& s, std::size_t chains, std::size_t nodes, std::size_t points) {
    grow_to(s.node_of, chains);
    grow_to(s.force, chains);
    grow_to(s.segments, chains);
    grow_to(s.load, chains);
    for (std::size_t c = 0; c < chains; ++c) {
        s.node_of[c].reserve(points);
        s.force[c].reserve(points);
        s.segments[c].reserve(points);
        s.load[c].reserve(points);
    }
    s.parent_node.reserve(nodes);
    s.diagonal.reserve(nodes);
    s.inverse.reserve(nodes);
    s.to_parent.reserve(nodes);
    s.to_grandparent.reserve(nodes);
    s.topology.reserve(3 * chains);
    for (auto* v : {&s.rhs, &s.fixed_velocity, &s.node_force, &s.held_position, &s.wall_normal}) v->reserve(nodes);
    for (auto* v : {&s.fixed, &s.resting, &s.on_rim}) v->reserve(nodes);
    s.rim.reserve(points);
    s.frame_gradient_nm.reserve(chains);
    s.frame_stiffness_nm.reserve(chains);
}

bool step_tree(std::span<const TreeChain> chains, glm::dvec3 gravity, double dt, TreeScratch& s, bool end_forces, const TreeSupport* support) {
    if (chains.empty()) return true;
    for (std::size_t c = 1; c < chains.size(); ++c) {
        if (!valid_fork(chains, c)) return false;
    }
    // A twig's P0 is its parent's point: whatever moved one of them since the last step (a table pushing
    // a point up, a hand), the parent's is the one that counts.
    for (std::size_t c = 1; c < chains.size(); ++c) {
        const auto& parent = *chains[static_cast<std::size_t>(chains[c].parent)].points;
        chains[c].points->position_m[0] = parent.position_m[chains[c].fork->at_point];
        chains[c].points->velocity_m_s[0] = parent.velocity_m_s[chains[c].fork->at_point];
    }
    number_nodes(chains, s);
    const std::size_t n = s.parent_node.size();
    s.diagonal.assign(n, Sym3{});
    s.to_parent.assign(n, Block3{});
    s.to_grandparent.assign(n, 0.0);
    s.inverse.resize(n);
    s.rhs.assign(n, glm::dvec3{0.0});
    s.fixed.assign(n, 0);
    s.resting.assign(n, 0);
    s.wall_normal.assign(n, glm::dvec3{0.0});
    s.on_rim.assign(n, 0);
    s.fixed_velocity.assign(n, glm::dvec3{0.0});
    grow_to(s.force, chains.size());
    grow_to(s.segments, chains.size());
    const auto parent_of = [&](std::uint32_t node) { return s.parent_node[node]; };

    // Forces at the step's start: each chain's own, then the root hinges'.
    for (std::size_t c = 0; c < chains.size(); ++c) {
        const auto& chain = chains[c];
        stem_forces(*chain.points, *chain.rest, *chain.springs, clamped(chain) ? chain.clamp : nullptr, gravity, s.force[c], s.segments[c], chain.frame);
    }
    // The system A v' = M v + h f, A = M (1 + h alpha) + (h beta + h^2) H, block by block; each chain's
    // own alpha and beta on its masses and springs (the root hinge: the twig's).
    for (std::size_t c = 0; c < chains.size(); ++c) {
        const auto& chain = chains[c];
        const auto& points = *chain.points;
        const auto& rest = *chain.rest;
        const auto& springs = *chain.springs;
        const auto& nodes = s.node_of[c];
        const std::size_t count = points.position_m.size();
        const double scale = dt * springs.stiffness_damping_s + dt * dt;
        for (std::size_t j = 0; j < count; ++j) {
            const std::uint32_t q = nodes[j];
            add_scalar(s.diagonal[q], points.mass_kg[j] * (1.0 + dt * springs.air_drag_per_s));
            s.rhs[q] += points.mass_kg[j] * points.velocity_m_s[j] + dt * s.force[c][j];
            const bool fixed = points.pinned[j] != 0 || (j == 0 && clamped(chain));
            if (fixed && !s.fixed[q]) {
                s.fixed[q] = 1;
                s.fixed_velocity[q] = points.velocity_m_s[j];
            }
        }
        // Segments: the axial Hessian with its tension's transverse part (stem_dynamics' assemble_step).
        for (std::size_t i = 1; i < count; ++i) {
            const StemSegment& seg = s.segments[c][i - 1];
            if (seg.length_m <= 0.0) continue;
            const double k = springs.axial_n_per_m[i - 1];
            const double transverse = std::max(0.0, 1.0 - rest.segment_length_m[i - 1] / seg.length_m);
            const double along = scale * k * (1.0 - transverse), across_ = scale * k * transverse;
            const glm::dvec3 e = seg.direction;
            const Sym3 block{along * e.x * e.x + across_, along * e.x * e.y, along * e.x * e.z,
                             along * e.y * e.y + across_, along * e.y * e.z, along * e.z * e.z + across_};
            const std::uint32_t a = nodes[i - 1], b = nodes[i];
            for (std::size_t m = 0; m < 6; ++m) {
                s.diagonal[a][m] += block[m];
                s.diagonal[b][m] += block[m];
            }
            Block3& up = s.to_parent[b]; // b's parent is a
            up[0] -= block[0], up[1] -= block[1], up[2] -= block[2];
            up[3] -= block[1], up[4] -= block[3], up[5] -= block[4];
            up[6] -= block[2], up[7] -= block[4], up[8] -= block[5];
        }
        // Hinges: the small-angle Hessian k c c^T on every axis alike.
        const auto hinge = [&](std::uint32_t a, std::uint32_t b, std::uint32_t top, double k, double l_in, double l_out) {
            const double c0 = 1.0 / l_in, c2 = 1.0 / l_out, c1 = -(c0 + c2);
            const double ks = k * scale;
            add_scalar(s.diagonal[a], ks * c0 * c0);
            add_scalar(s.diagonal[b], ks * c1 * c1);
            add_scalar(s.diagonal[top], ks * c2 * c2);
            add_scalar(s.to_parent[b], ks * c1 * c0);
            add_scalar(s.to_parent[top], ks * c2 * c1);
            s.to_grandparent[top] += ks * c2 * c0;
        };
        for (std::size_t i = 1; i + 1 < count; ++i) {
            hinge(nodes[i - 1], nodes[i], nodes[i + 1], springs.hinge_nm_per_rad[i - 1], rest.segment_length_m[i - 1], rest.segment_length_m[i]);
        }
        if (clamped(chain) && count >= 2) {
            const double kc = scale * chain.clamp->hinge_nm_per_rad / (rest.segment_length_m[0] * rest.segment_length_m[0]);
            add_scalar(s.diagonal[nodes[0]], kc);
            add_scalar(s.diagonal[nodes[1]], kc);
            add_scalar(s.to_parent[nodes[1]], -kc);
        }
        if (c > 0) {
            const auto& parent = chains[static_cast<std::size_t>(chain.parent)];
            const auto& parent_nodes = s.node_of[static_cast<std::size_t>(chain.parent)];
            const std::uint32_t k = chain.fork->at_point;
            const std::uint32_t below = parent_nodes[k - 1], at = parent_nodes[k], above = nodes[1];
            hinge(below, at, above, chain.fork->hinge_nm_per_rad, parent.rest->segment_length_m[k - 1], rest.segment_length_m[0]);
            const RootHinge h = root_hinge(chains, c);
            s.rhs[below] += dt * h.f_below;
            s.rhs[above] += dt * h.f_above;
            s.rhs[at] -= dt * (h.f_below + h.f_above);
        }
    }
    // What it rests on: a point below its floor (the shared point once, as its parent's) is pushed up by
    // a stiff damped spring, implicit: h^2 k + h c on its vertical diagonal, h k (floor - z) its impulse.
    // What it lies across (a rim): the spring on the supported point's height, on both ends' z and
    // their coupling (stem_dynamics' assemble_step; b's parent in the numbering is a).
    if (support && support->rim_m) {
        const double w = dt * dt * support->stiffness_n_per_m + dt * support->damping_n_s_per_m;
        for (std::size_t c = 0; c < chains.size(); ++c) {
            const auto& x = chains[c].points->position_m;
            support->rim_m(support->context, x, 0.5 * chains[c].rest->diameter_m, s.rim);
            for (const SegmentSupport& on : s.rim) {
                if (on.segment + 1 >= x.size()) continue;
                const std::uint32_t a = s.node_of[c][on.segment], b = s.node_of[c][on.segment + 1];
                if (s.parent_node[b] != static_cast<std::int32_t>(a)) continue;
                s.on_rim[a] = s.on_rim[b] = 1;
                const double wa = 1.0 - on.t, wb = on.t;
                // Raised at most exit_speed a step (the floors' rule below): found deep under the rim, it
                // would be flung.
                const double below = std::min(on.top_m - (wa * x[on.segment].z + wb * x[on.segment + 1].z), support->exit_speed_m_s * dt);
                if (below <= 0.0) continue;
                s.diagonal[a][5] += w * wa * wa;
                s.diagonal[b][5] += w * wb * wb;
                s.to_parent[b][8] += w * wa * wb;
                s.rhs[a].z += dt * support->stiffness_n_per_m * below * wa;
                s.rhs[b].z += dt * support->stiffness_n_per_m * below * wb;
            }
        }
    }
    if (support && support->floor_m) {
        for (std::size_t c = 0; c < chains.size(); ++c) {
            const auto& points = *chains[c].points;
            const double radius = 0.5 * chains[c].rest->diameter_m;
            for (std::size_t j = (c > 0 ? 1 : 0); j < points.position_m.size(); ++j) {
                const glm::dvec3 x = points.position_m[j];
                double end_drop = radius;
                if (c == 0 && j == 0 && points.position_m.size() >= 2) {
                    const glm::dvec3 axis = points.position_m[1] - x;
                    const double length = glm::length(axis);
                    end_drop = length > 0.0 ? radius * std::sqrt(std::max(0.0, 1.0 - axis.z * axis.z / (length * length))) : radius;
                }
                const std::uint32_t q = s.node_of[c][j];
                if (support->wall_push_m && !s.on_rim[q]) {
                    const glm::dvec3 push = support->wall_push_m(support->context, x, radius);
                    const double depth = glm::length(push);
                    if (depth > 0.0) {
                        const glm::dvec3 out = push / depth;
                        s.wall_normal[q] = out;
                        const double w = dt * dt * support->stiffness_n_per_m + dt * support->damping_n_s_per_m;
                        Sym3& d = s.diagonal[q];
                        d[0] += w * out.x * out.x, d[1] += w * out.x * out.y, d[2] += w * out.x * out.z;
                        d[3] += w * out.y * out.y, d[4] += w * out.y * out.z, d[5] += w * out.z * out.z;
                        s.rhs[q] += dt * support->stiffness_n_per_m * push;
                    }
                }
                const double floor = support->floor_m(support->context, {x.x, x.y}, radius, end_drop);
                if (x.z >= floor) continue;
                s.resting[q] = 1;
                s.diagonal[q][5] += dt * dt * support->stiffness_n_per_m + dt * support->damping_n_s_per_m;
                s.rhs[q].z += dt * support->stiffness_n_per_m * (floor - x.z);
            }
        }
    }
    // Fixed points keep v' = 0; a held one moving with the hand drags its neighbours: its column's A v
    // goes to the right-hand side first, then its rows and columns become the identity's.
    for (std::uint32_t q = 0; q < n; ++q) {
        const std::int32_t p = parent_of(q);
        const std::int32_t g = p >= 0 ? parent_of(static_cast<std::uint32_t>(p)) : -1;
        if (p >= 0 && s.fixed[static_cast<std::size_t>(p)]) s.rhs[q] -= times(s.to_parent[q], s.fixed_velocity[static_cast<std::size_t>(p)]);
        if (g >= 0 && s.fixed[static_cast<std::size_t>(g)]) s.rhs[q] -= s.to_grandparent[q] * s.fixed_velocity[static_cast<std::size_t>(g)];
        if (s.fixed[q]) {
            if (p >= 0) s.rhs[static_cast<std::size_t>(p)] -= transposed_times(s.to_parent[q], s.fixed_velocity[q]);
            if (g >= 0) s.rhs[static_cast<std::size_t>(g)] -= s.to_grandparent[q] * s.fixed_velocity[q];
        }
    }
    for (std::uint32_t q = 0; q < n; ++q) {
        const std::int32_t p = parent_of(q);
        const std::int32_t g = p >= 0 ? parent_of(static_cast<std::uint32_t>(p)) : -1;
        if (s.fixed[q] || (p >= 0 && s.fixed[static_cast<std::size_t>(p)])) s.to_parent[q] = Block3{};
        if (s.fixed[q] || (g >= 0 && s.fixed[static_cast<std::size_t>(g)])) s.to_grandparent[q] = 0.0;
        if (s.fixed[q]) {
            s.diagonal[q] = Sym3{1.0, 0.0, 0.0, 1.0, 0.0, 1.0};
            s.rhs[q] = glm::dvec3{0.0};
        }
    }
    // L D L^T from the leaves up. A(q, p) is B = to_parent[q] (rows q's axes), A(p, q) its transpose;
    // with W = D_q^-1 B and y = D_q^-1 b_q, eliminating q takes B^T W from D_p (symmetric: six entries),
    // B^T y from b_p, and through the grandparent's scalar coupling gq: gq^2 D_q^-1 from D_g, gq y from
    // b_g, gq W^T from A(p, g).
    for (std::uint32_t q = static_cast<std::uint32_t>(n); q-- > 0;) {
        const Sym3& d = s.inverse[q];
        if (!invert_positive(s.diagonal[q], s.inverse[q])) return false;
        const std::int32_t p = parent_of(q);
        if (p < 0) continue;
        const auto pi = static_cast<std::size_t>(p);
        const Block3& b = s.to_parent[q];
        Block3 w; // D^-1 B
        for (std::size_t c = 0; c < 3; ++c) {
            w[c] = d[0] * b[c] + d[1] * b[3 + c] + d[2] * b[6 + c];
            w[3 + c] = d[1] * b[c] + d[3] * b[3 + c] + d[4] * b[6 + c];
            w[6 + c] = d[2] * b[c] + d[4] * b[3 + c] + d[5] * b[6 + c];
        }
        const auto column_dot = [&](std::size_t i, std::size_t j) { return b[i] * w[j] + b[3 + i] * w[3 + j] + b[6 + i] * w[6 + j]; };
        Sym3& dp = s.diagonal[pi];
        dp[0] -= column_dot(0, 0), dp[1] -= column_dot(0, 1), dp[2] -= column_dot(0, 2);
        dp[3] -= column_dot(1, 1), dp[4] -= column_dot(1, 2), dp[5] -= column_dot(2, 2);
        const glm::dvec3 y = times(d, s.rhs[q]);
        s.rhs[pi] -= transposed_times(b, y);
        const std::int32_t g = parent_of(static_cast<std::uint32_t>(p));
        if (g < 0) continue;
        const auto gi = static_cast<std::size_t>(g);
        const double gq = s.to_grandparent[q];
        if (gq == 0.0) continue;
        Sym3& dg = s.diagonal[gi];
        for (std::size_t m = 0; m < 6; ++m) dg[m] -= gq * gq * d[m];
        s.rhs[gi] -= gq * y;
        Block3& pg = s.to_parent[pi];
        for (std::size_t i = 0; i < 3; ++i) {
            for (std::size_t j = 0; j < 3; ++j) pg[3 * i + j] -= gq * w[3 * j + i];
        }
    }
    // Back up from the root: v_q = D_q^-1 (b_q - A(q, p) v_p - A(q, g) v_g), in place in rhs.
    for (std::uint32_t q = 0; q < n; ++q) {
        glm::dvec3 b = s.rhs[q];
        const std::int32_t p = parent_of(q);
        if (p >= 0) {
            b -= times(s.to_parent[q], s.rhs[static_cast<std::size_t>(p)]);
            const std::int32_t g = parent_of(static_cast<std::uint32_t>(p));
            if (g >= 0) b -= s.to_grandparent[q] * s.rhs[static_cast<std::size_t>(g)];
        }
        s.rhs[q] = times(s.inverse[q], b);
        if (!std::isfinite(s.rhs[q].x) || !std::isfinite(s.rhs[q].y) || !std::isfinite(s.rhs[q].z)) return false;
    }
    // Resting points slide with Coulomb friction: at most mu g h of their sliding speed lost a step. And
    // leave their floor no faster than exit_speed: the spring puts a point back in one step, and one found
    // deep inside (a twig laid through a vase's fill, a hand pressing a branch down faster than the
    // spring answers) would be flung out; it is raised over ticks instead.
    if (support) {
        const double loss = support->friction * support->gravity_m_s2 * dt;
        for (std::uint32_t q = 0; q < n; ++q) {
            if (s.fixed[q]) continue;
            glm::dvec3& v = s.rhs[q];
            if (const glm::dvec3 w = s.wall_normal[q]; w != glm::dvec3{0.0}) {
                const double out = glm::dot(v, w);
                if (out > support->exit_speed_m_s) v -= (out - support->exit_speed_m_s) * w;
            }
            if (!s.resting[q]) continue;
            v.z = std::min(v.z, support->exit_speed_m_s);
            const double speed = std::sqrt(v.x * v.x + v.y * v.y);
            const double keep = speed > loss ? 1.0 - loss / speed : 0.0;
            v.x *= keep;
            v.y *= keep;
        }
    }
    // Positions: every chain's points from their nodes; a twig's P0 is its parent's point exactly.
    for (std::size_t c = 0; c < chains.size(); ++c) {
        auto& points = *chains[c].points;
        const auto& nodes = s.node_of[c];
        for (std::size_t j = 0; j < points.position_m.size(); ++j) {
            if (c > 0 && j == 0) continue;
            const std::uint32_t q = nodes[j];
            if (s.fixed[q]) {
                points.velocity_m_s[j] = glm::dvec3{0.0};
                if (j == 0 && clamped(chains[c])) points.position_m[0] = chains[c].clamp->anchor_m;
                continue;
            }
            points.velocity_m_s[j] = s.rhs[q];
            points.position_m[j] += dt * s.rhs[q];
        }
        if (c > 0) {
            const auto& parent = *chains[static_cast<std::size_t>(chains[c].parent)].points;
            points.position_m[0] = parent.position_m[chains[c].fork->at_point];
            points.velocity_m_s[0] = parent.velocity_m_s[chains[c].fork->at_point];
        }
    }
    // The body's own forces on each point, summed over a shared point's chains. A held point is where
    // the grab will put it, a step on at the velocity the solve took it to move with (as for a chain:
    // stem_dynamics' finish_step): left behind, its neighbours gone on with the hand pulled it back.
    const auto shift_held = [&](bool forward) {
        std::size_t k = 0;
        if (forward) s.held_position.clear();
        for (std::size_t c = 0; c < chains.size(); ++c) {
            auto& points = *chains[c].points;
            for (std::size_t j = 0; j < points.position_m.size(); ++j) {
                const std::uint32_t q = s.node_of[c][j];
                if (!s.fixed[q] || (c == 0 && j == 0 && clamped(chains[c]))) continue;
                if (forward) {
                    s.held_position.push_back(points.position_m[j]);
                    points.position_m[j] += dt * s.fixed_velocity[q];
                } else {
                    points.position_m[j] = s.held_position[k++]; // exactly where it was
                }
            }
        }
    };
    if (end_forces) {
        shift_held(true);
        for (std::size_t c = 0; c < chains.size(); ++c) {
            const auto& chain = chains[c];
            stem_forces(*chain.points, *chain.rest, *chain.springs, clamped(chain) ? chain.clamp : nullptr, gravity, s.force[c], s.segments[c], chain.frame);
        }
    }
    s.node_force.assign(n, glm::dvec3{0.0});
    s.frame_gradient_nm.assign(chains.size(), 0.0);
    s.frame_stiffness_nm.assign(chains.size(), 0.0);
    for (std::size_t c = 0; c < chains.size(); ++c) {
        const auto& points = *chains[c].points;
        for (std::size_t j = 0; j < points.position_m.size(); ++j) s.node_force[s.node_of[c][j]] += s.force[c][j] - points.external_force_n[j];
        if (c == 0) continue;
        const RootHinge h = root_hinge(chains, c);
        const auto& parent_nodes = s.node_of[static_cast<std::size_t>(chains[c].parent)];
        s.node_force[parent_nodes[h.below]] += h.f_below;
        s.node_force[s.node_of[c][h.above]] += h.f_above;
        s.node_force[parent_nodes[h.at]] -= h.f_below + h.f_above;
        s.frame_gradient_nm[c] = h.frame_gradient_nm;
        s.frame_stiffness_nm[c] = h.frame_stiffness_nm;
    }
    if (end_forces) shift_held(false);
    grow_to(s.load, chains.size());
    for (std::size_t c = 0; c < chains.size(); ++c) {
        const auto& nodes = s.node_of[c];
        s.load[c].resize(nodes.size());
        for (std::size_t j = 0; j < nodes.size(); ++j) s.load[c][j] = s.node_force[nodes[j]];
    }
    return true;
}

StemEnergy tree_energy(std::span<const TreeChain> chains, glm::dvec3 gravity) {
    StemEnergy total;
    for (std::size_t c = 0; c < chains.size(); ++c) {
        const auto& chain = chains[c];
        const StemEnergy e = stem_energy(*chain.points, *chain.rest, *chain.springs, clamped(chain) ? chain.clamp : nullptr, gravity, chain.frame);
        total.kinetic_j += e.kinetic_j;
        total.elastic_j += e.elastic_j;
        total.gravitational_j += e.gravitational_j;
        if (c > 0 && valid_fork(chains, c)) total.elastic_j += root_hinge(chains, c).energy_j;
    }
    return total;
}

} // namespace ikebana::systems::physics
