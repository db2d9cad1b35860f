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
    s.node_of.resize(chains.size());
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

// Sylvester's test and the inverse of a symmetric 3x3 block.
bool invert_positive(const glm::dmat3& m, glm::dmat3& out) {
    const double a = m[0][0];
    const double minor = m[0][0] * m[1][1] - m[0][1] * m[1][0];
    const double det = glm::determinant(m);
    if (!(a > 0.0 && minor > 0.0 && det > 0.0)) return false;
    out = glm::inverse(m);
    return true;
}

glm::dmat3 scalar(double v) { return glm::dmat3(v); }

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

std::size_t tree_substeps(std::span<const TreeChain> chains, double dt) {
    std::size_t parts = 1;
    for (std::size_t c = 0; c < chains.size(); ++c) {
        const auto& chain = chains[c];
        parts = std::max(parts, stable_substeps(*chain.points, *chain.rest, *chain.springs, c == 0 ? chain.clamp : nullptr, dt));
        if (!valid_fork(chains, c)) continue;
        // The root hinge as stable_substeps takes a hinge: k (1/l_in + 1/l_out)^2 over the shared point's mass.
        const auto& parent = chains[static_cast<std::size_t>(chain.parent)];
        const std::uint32_t k = chain.fork->at_point;
        const double l_in = parent.rest->segment_length_m[k - 1], l_out = chain.rest->segment_length_m[0];
        const double mass = parent.points->mass_kg[k] + chain.points->mass_kg[0];
        const double omega_squared = chain.fork->hinge_nm_per_rad * std::pow(1.0 / l_in + 1.0 / l_out, 2) / mass;
        const double steps = std::ceil(std::sqrt(omega_squared) * dt / max_omega_dt);
        if (std::isfinite(steps) && steps > 1.0) parts = std::max(parts, std::min(max_substeps, static_cast<std::size_t>(steps)));
    }
    return parts;
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
    s.diagonal.assign(n, glm::dmat3(0.0));
    s.to_parent.assign(n, glm::dmat3(0.0));
    s.to_grandparent.assign(n, 0.0);
    s.inverse.resize(n);
    s.rhs.assign(n, glm::dvec3{0.0});
    s.fixed.assign(n, 0);
    s.resting.assign(n, 0);
    s.wall_normal.assign(n, glm::dvec3{0.0});
    s.fixed_velocity.assign(n, glm::dvec3{0.0});
    s.force.resize(chains.size());
    s.segments.resize(chains.size());
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
            s.diagonal[q] += scalar(points.mass_kg[j] * (1.0 + dt * springs.air_drag_per_s));
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
            const glm::dmat3 block = scale * (k * (1.0 - transverse) * glm::outerProduct(seg.direction, seg.direction) + scalar(k * transverse));
            const std::uint32_t a = nodes[i - 1], b = nodes[i];
            s.diagonal[a] += block;
            s.diagonal[b] += block;
            s.to_parent[b] -= block; // b's parent is a
        }
        // Hinges: the small-angle Hessian k c c^T on every axis alike.
        const auto hinge = [&](std::uint32_t a, std::uint32_t b, std::uint32_t top, double k, double l_in, double l_out) {
            const double c0 = 1.0 / l_in, c2 = 1.0 / l_out, c1 = -(c0 + c2);
            const double ks = k * scale;
            s.diagonal[a] += scalar(ks * c0 * c0);
            s.diagonal[b] += scalar(ks * c1 * c1);
            s.diagonal[top] += scalar(ks * c2 * c2);
            s.to_parent[b] += scalar(ks * c1 * c0);
            s.to_parent[top] += scalar(ks * c2 * c1);
            s.to_grandparent[top] += ks * c2 * c0;
        };
        for (std::size_t i = 1; i + 1 < count; ++i) {
            hinge(nodes[i - 1], nodes[i], nodes[i + 1], springs.hinge_nm_per_rad[i - 1], rest.segment_length_m[i - 1], rest.segment_length_m[i]);
        }
        if (clamped(chain) && count >= 2) {
            const double kc = scale * chain.clamp->hinge_nm_per_rad / (rest.segment_length_m[0] * rest.segment_length_m[0]);
            s.diagonal[nodes[0]] += scalar(kc);
            s.diagonal[nodes[1]] += scalar(kc);
            s.to_parent[nodes[1]] -= scalar(kc);
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
                if (support->wall_push_m) {
                    const glm::dvec3 push = support->wall_push_m(support->context, x, radius);
                    const double depth = glm::length(push);
                    if (depth > 0.0) {
                        const glm::dvec3 out = push / depth;
                        s.wall_normal[q] = out;
                        s.diagonal[q] += (dt * dt * support->stiffness_n_per_m + dt * support->damping_n_s_per_m) * glm::outerProduct(out, out);
                        s.rhs[q] += dt * support->stiffness_n_per_m * push;
                    }
                }
                const double floor = support->floor_m(support->context, {x.x, x.y}, radius, end_drop);
                if (x.z >= floor) continue;
                s.resting[q] = 1;
                s.diagonal[q][2][2] += dt * dt * support->stiffness_n_per_m + dt * support->damping_n_s_per_m;
                s.rhs[q].z += dt * support->stiffness_n_per_m * (floor - x.z);
            }
        }
    }
    // Fixed points keep v' = 0; a held one moving with the hand drags its neighbours: its column's A v
    // goes to the right-hand side first, then its rows and columns become the identity's.
    for (std::uint32_t q = 0; q < n; ++q) {
        const std::int32_t p = parent_of(q);
        const std::int32_t g = p >= 0 ? parent_of(static_cast<std::uint32_t>(p)) : -1;
        if (p >= 0 && s.fixed[static_cast<std::size_t>(p)]) s.rhs[q] -= s.to_parent[q] * s.fixed_velocity[static_cast<std::size_t>(p)];
        if (g >= 0 && s.fixed[static_cast<std::size_t>(g)]) s.rhs[q] -= s.to_grandparent[q] * s.fixed_velocity[static_cast<std::size_t>(g)];
        if (s.fixed[q]) {
            if (p >= 0) s.rhs[static_cast<std::size_t>(p)] -= glm::transpose(s.to_parent[q]) * s.fixed_velocity[q];
            if (g >= 0) s.rhs[static_cast<std::size_t>(g)] -= s.to_grandparent[q] * s.fixed_velocity[q];
        }
    }
    for (std::uint32_t q = 0; q < n; ++q) {
        const std::int32_t p = parent_of(q);
        const std::int32_t g = p >= 0 ? parent_of(static_cast<std::uint32_t>(p)) : -1;
        if (s.fixed[q] || (p >= 0 && s.fixed[static_cast<std::size_t>(p)])) s.to_parent[q] = glm::dmat3(0.0);
        if (s.fixed[q] || (g >= 0 && s.fixed[static_cast<std::size_t>(g)])) s.to_grandparent[q] = 0.0;
        if (s.fixed[q]) {
            s.diagonal[q] = glm::dmat3(1.0);
            s.rhs[q] = glm::dvec3{0.0};
        }
    }
    // L D L^T from the leaves up. A(q, p) is to_parent[q] (rows q's axes), A(p, q) its transpose.
    for (std::uint32_t q = static_cast<std::uint32_t>(n); q-- > 0;) {
        if (!invert_positive(s.diagonal[q], s.inverse[q])) return false;
        const std::int32_t p = parent_of(q);
        if (p < 0) continue;
        const auto pi = static_cast<std::size_t>(p);
        const glm::dmat3 up = glm::transpose(s.to_parent[q]) * s.inverse[q]; // A(p, q) D_q^-1
        s.diagonal[pi] -= up * s.to_parent[q];
        s.rhs[pi] -= up * s.rhs[q];
        const std::int32_t g = parent_of(static_cast<std::uint32_t>(p));
        if (g < 0) continue;
        const auto gi = static_cast<std::size_t>(g);
        const double gq = s.to_grandparent[q];
        if (gq == 0.0) continue;
        const glm::dmat3 far = gq * s.inverse[q]; // A(g, q) D_q^-1 (D_q^-1 is symmetric)
        s.diagonal[gi] -= gq * far;
        s.rhs[gi] -= far * s.rhs[q];
        s.to_parent[pi] -= gq * up; // A(p, g) -= A(p, q) D^-1 A(q, g)
    }
    // Back up from the root: v_q = D_q^-1 (b_q - A(q, p) v_p - A(q, g) v_g), in place in rhs.
    for (std::uint32_t q = 0; q < n; ++q) {
        glm::dvec3 b = s.rhs[q];
        const std::int32_t p = parent_of(q);
        if (p >= 0) {
            b -= s.to_parent[q] * s.rhs[static_cast<std::size_t>(p)];
            const std::int32_t g = parent_of(static_cast<std::uint32_t>(p));
            if (g >= 0) b -= s.to_grandparent[q] * s.rhs[static_cast<std::size_t>(g)];
        }
        s.rhs[q] = s.inverse[q] * b;
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
    // The body's own forces on each point, summed over a shared point's chains.
    if (end_forces) {
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
    s.load.resize(chains.size());
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
