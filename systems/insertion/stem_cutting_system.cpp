#include "systems/insertion/stem_cutting_system.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "engine/ecs/registry.hpp"

namespace ikebana::systems {

using namespace components;

void moved_bends_into(const StemRestShape& rest, double cut_m, double keep, CutScratch& scratch, std::vector<double>& moved) {
    const auto& l = rest.segment_length_m;
    const auto& angle = rest.hinge_angle_rad;
    if (angle.empty() || angle.size() + 1 != l.size()) {
        moved.assign(angle.begin(), angle.end());
        return;
    }
    // Hinge j sits at the top of segment j; its curvature spreads over half of each segment beside it.
    auto& at = scratch.at;
    auto& curvature = scratch.curvature;
    at.resize(angle.size());
    curvature.resize(angle.size());
    double s = 0.0;
    for (std::size_t j = 0; j < angle.size(); ++j) {
        s += l[j];
        at[j] = s;
        curvature[j] = angle[j] / std::max(0.5 * (l[j] + l[j + 1]), 1e-12);
    }
    const auto curvature_at = [&](double x) {
        if (x <= at.front()) return curvature.front();
        if (x >= at.back()) return curvature.back();
        const std::size_t j = static_cast<std::size_t>(std::upper_bound(at.begin(), at.end(), x) - at.begin());
        const double t = (x - at[j - 1]) / std::max(at[j] - at[j - 1], 1e-12);
        return curvature[j - 1] + t * (curvature[j] - curvature[j - 1]);
    };
    moved.resize(angle.size());
    double from = cut_m;
    for (std::size_t j = 0; j < angle.size(); ++j) {
        from += l[j] * keep;
        moved[j] = curvature_at(from) * 0.5 * (l[j] + l[j + 1]) * keep;
    }
}

std::vector<double> moved_bends(const StemRestShape& rest, double cut_m, double keep) {
    CutScratch scratch;
    std::vector<double> moved;
    moved_bends_into(rest, cut_m, keep, scratch, moved);
    return moved;
}

void moved_bend_directions_into(const StemRestShape& rest, double cut_m, double keep, CutScratch& scratch, std::vector<glm::dvec2>& moved) {
    const auto& l = rest.segment_length_m;
    const auto& direction = rest.hinge_bend_direction;
    if (direction.empty() || direction.size() + 1 != l.size()) {
        moved.assign(direction.begin(), direction.end());
        return;
    }
    // As moved_bends: each new hinge takes the direction of the old hinge nearest where it now sits.
    auto& at = scratch.at;
    at.resize(direction.size());
    double s = 0.0;
    for (std::size_t j = 0; j < direction.size(); ++j) at[j] = (s += l[j]);
    moved.resize(direction.size());
    double from = cut_m;
    std::size_t nearest = 0;
    for (std::size_t j = 0; j < direction.size(); ++j) {
        from += l[j] * keep;
        while (nearest + 1 < at.size() && std::abs(at[nearest + 1] - from) <= std::abs(at[nearest] - from)) ++nearest;
        moved[j] = direction[nearest];
    }
}

void move_twigs(ecs::Registry& r, ecs::Entity flower, const std::vector<glm::dvec3>& before, const std::vector<glm::dvec3>& after, double cut_m,
                double length_m, CutScratch& scratch) {
    auto* twigs = r.try_get<Twigs>(flower);
    if (!twigs || before.size() < 2) return;
    const std::size_t segments = before.size() - 1;
    // The stem's points were laid anew along it, closer together: a twig stays where it grows on the
    // stem (its arc length less the cut), at the nearest point there; one that grew from the part cut
    // off goes with it, and so do its own twigs. A twig and its twigs move as one to their new place.
    auto& moved = scratch.twig_moved;
    auto& gone = scratch.twig_gone;
    auto& kept = scratch.kept;
    moved.assign(twigs->entities.size(), glm::dvec3{0.0});
    gone.assign(twigs->entities.size(), 0);
    kept.clear();
    for (std::size_t t = 0; t < twigs->entities.size(); ++t) {
        const ecs::Entity twig = twigs->entities[t];
        auto* fork = r.try_get<StemFork>(twig);
        auto* twig_points = r.try_get<StemPoints>(twig);
        if (!fork || !twig_points) {
            gone[t] = 1;
            continue;
        }
        if (fork->parent == flower) {
            const double along = length_m * static_cast<double>(fork->at_point) / static_cast<double>(segments) - cut_m;
            const double step = (length_m - cut_m) / static_cast<double>(segments);
            if (along < 0.5 * step) {
                gone[t] = 1;
            } else {
                fork->at_point = static_cast<std::uint32_t>(std::clamp<long>(std::lround(along / step), 1, static_cast<long>(segments)));
                moved[t] = after[fork->at_point] - twig_points->position_m[0];
            }
        } else {
            const auto parent = std::find(twigs->entities.begin(), twigs->entities.begin() + static_cast<long>(t), fork->parent);
            const auto p = static_cast<std::size_t>(parent - twigs->entities.begin());
            if (p == t || gone[p]) gone[t] = 1;
            else moved[t] = moved[p];
        }
        if (gone[t]) {
            r.commands().destroy(twig); // its leaves and blossoms (its children) with it
            continue;
        }
        for (auto& x : twig_points->position_m) x += moved[t];
        for (auto& v : twig_points->velocity_m_s) v = glm::dvec3{0.0};
        kept.push_back(twig);
    }
    twigs->entities.assign(kept.begin(), kept.end()); // fewer than it had: within its capacity
}

void move_parts(ecs::Registry& r, ecs::Entity flower, std::size_t segments, double cut_m, double length_m, CutScratch& scratch) {
    const auto* children = r.try_get<const ecs::Children>(flower);
    if (!children || segments == 0) return;
    const double step = (length_m - cut_m) / static_cast<double>(segments);
    auto& gone = scratch.gone;
    gone.clear();
    for (const ecs::Entity child : children->entities) {
        auto* part = r.try_get<Part>(child);
        if (!part || part->kind == PartKind::stem) continue;
        const double along = length_m * static_cast<double>(part->stem_point) / static_cast<double>(segments) - cut_m;
        if (along < 0.5 * step) {
            gone.push_back(child);
            continue;
        }
        part->stem_point = static_cast<std::uint32_t>(std::clamp<long>(std::lround(along / step), 1, static_cast<long>(segments)));
    }
    for (const ecs::Entity child : gone) r.commands().destroy(child); // with the part cut off
}

void StemCuttingSystem::operator()(sched::SystemContext& ctx) {
    auto& r = ctx.registry;
    // The scratch the scene reserved (a registry built without one, as some tests build theirs, makes its own).
    auto* reserve = r.resource<StructureReserve>();
    CutScratch own;
    CutScratch& scratch = reserve ? reserve->cut : own;
    r.view<CutRequest, StemPoints, StemRestShape, StemSprings, InsertionHistory>().each(
        [&](ecs::Entity e, CutRequest& cut, StemPoints& points, StemRestShape& rest, StemSprings& springs,
            InsertionHistory& history) {
            r.commands().remove<CutRequest>(e);
            const double length = std::accumulate(rest.segment_length_m.begin(), rest.segment_length_m.end(), 0.0);
            if (!(cut.length_m > 0.0) || length - cut.length_m < shortest_stem_m) return;
            const double keep = (length - cut.length_m) / length;
            // The new points: the old polyline resampled from arc length `cut` upwards.
            const auto& old = points.position_m;
            auto& before = scratch.before; // where its twigs left it
            auto& fresh = scratch.fresh;
            auto& arc = scratch.arc;
            before.assign(old.begin(), old.end());
            fresh.resize(old.size());
            arc.assign(old.size(), 0.0);
            for (std::size_t i = 1; i < old.size(); ++i) arc[i] = arc[i - 1] + glm::length(old[i] - old[i - 1]);
            const double total = arc.back();
            for (std::size_t i = 0; i < old.size(); ++i) {
                const double s = total * (cut.length_m / length) + total * keep * static_cast<double>(i) / static_cast<double>(old.size() - 1);
                const auto it = std::upper_bound(arc.begin(), arc.end(), s);
                const std::size_t j = std::clamp<std::size_t>(static_cast<std::size_t>(it - arc.begin()), 1, old.size() - 1);
                const double span = arc[j] - arc[j - 1];
                const double t = span > 0.0 ? std::clamp((s - arc[j - 1]) / span, 0.0, 1.0) : 0.0;
                fresh[i] = old[j - 1] + t * (old[j] - old[j - 1]);
            }
            // Mass: the stem's own mass shrinks with its length; what the top point carries beyond
            // its share of stem (the head) stays.
            const double stem_share = points.mass_kg.front() * 2.0; // a lumped segment's mass
            const double head = points.mass_kg.back() - 0.5 * stem_share;
            for (auto& m : points.mass_kg) m *= keep;
            points.mass_kg.back() = 0.5 * stem_share * keep + head;
            // The rest shape's bends stay where they are on the stem, not at the same point numbers: a
            // branch bent 150 mm below its tip is still bent there after its bottom is cut (the points
            // were laid anew closer together). Curvature (a hinge's angle over its share of length) is
            // carried over by arc length, and the new hinges take it over their shorter share.
            moved_bend_directions_into(rest, cut.length_m, keep, scratch, scratch.direction);
            moved_bends_into(rest, cut.length_m, keep, scratch, scratch.angle);
            rest.hinge_bend_direction.assign(scratch.direction.begin(), scratch.direction.end());
            rest.hinge_angle_rad.assign(scratch.angle.begin(), scratch.angle.end());
            for (auto& l : rest.segment_length_m) l *= keep;
            for (auto& k : springs.axial_n_per_m) k /= keep;
            for (auto& k : springs.hinge_nm_per_rad) k /= keep;
            points.position_m.assign(fresh.begin(), fresh.end()); // as many as it had: within its capacity
            for (auto& v : points.velocity_m_s) v = glm::dvec3{0.0};
            move_twigs(r, e, before, points.position_m, cut.length_m, length, scratch);
            move_parts(r, e, points.position_m.size() - 1, cut.length_m, length, scratch);
            history.bottom_broken = false;
            history.insertions = 0;
            history.holes.clear();
            ++history.cuts;
            history.cut_at_us = ctx.time_us;
        });
}

} // namespace ikebana::systems
