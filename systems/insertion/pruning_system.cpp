#include "systems/insertion/pruning_system.hpp"

#include <algorithm>
#include <limits>
#include <optional>
#include <vector>

#include "components/collision.hpp"
#include "engine/ecs/registry.hpp"
#include "systems/physics/part_attachment.hpp"
#include "systems/physics/stem_builder.hpp"
#include "systems/physics/stem_frame.hpp"

namespace ikebana::systems {

using namespace components;

namespace {

// The nearest thing a hand at `at` can prune, within `reach` of it.
using Found = PruningSystem::Found;

double to_segment(glm::dvec3 p, glm::dvec3 a, glm::dvec3 b) {
    const glm::dvec3 ab = b - a;
    const double len2 = glm::dot(ab, ab);
    const double t = len2 > 0.0 ? std::clamp(glm::dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
    return glm::length(p - (a + t * ab));
}


void consider_parts(ecs::Registry& r, ecs::Entity flower, ecs::Entity owner, glm::dvec3 at, double reach, Found& found) {
    const auto* children = r.try_get<const ecs::Children>(owner);
    const auto* points = r.try_get<const StemPoints>(owner);
    if (!children || !points || points->position_m.empty()) return;
    const auto* frame = r.try_get<const StemFrame>(owner);
    for (const ecs::Entity child : children->entities) {
        const auto* part = r.try_get<const Part>(child);
        if (!part || part->kind == PartKind::stem || part->mesh.empty()) continue;
        const double d = glm::length(part_middle(*part, *points, frame) - at);
        if (d <= reach && d < found.distance_m) found = {d, flower, ecs::null_entity, child, owner};
    }
}

// A loose stem of `points` (a stripped leaf's stalk), with a frame and the look of its flower.
ecs::Entity loose_stem(ecs::Registry& r, const std::vector<glm::dvec3>& x, double diameter_m, double mass_kg, const std::string& species,
                       const FlowerLook* look) {
    physics::StemSpec spec;
    spec.segments = static_cast<std::uint32_t>(x.size() - 1);
    spec.length_m = glm::length(x.back() - x.front());
    spec.diameter_m = diameter_m;
    spec.youngs_modulus_pa = 5.0e7;
    spec.stem_mass_kg = mass_kg;
    spec.base_m = x.front();
    spec.direction = glm::normalize(x.back() - x.front());
    auto built = physics::build_stem(spec);
    const ecs::Entity e = r.create();
    const auto count = built.points.position_m.size();
    r.emplace<StemPoints>(e, std::move(built.points));
    r.emplace<StemRestShape>(e, std::move(built.rest));
    r.emplace<StemSprings>(e, std::move(built.springs));
    r.emplace<StemFrame>(e, std::move(built.frame));
    r.emplace<StemLoads>(e, StemLoads{std::vector<glm::dvec3>(count, glm::dvec3{0.0})});
    r.emplace<Cutting>(e, Cutting{species});
    if (look) r.emplace<FlowerLook>(e, *look);
    return e;
}

// `v` turned by the least rotation that takes +z to `dir` (a unit vector).
glm::dvec3 turned_from_up(glm::dvec3 v, glm::dvec3 dir) {
    const glm::dvec3 axis{-dir.y, dir.x, 0.0}; // z x dir
    const double sin_angle = glm::length(axis);
    if (sin_angle < 1e-12) return dir.z > 0.0 ? v : glm::dvec3{v.x, -v.y, -v.z}; // half a turn about x
    const glm::dvec3 k = axis / sin_angle;
    const double cos_angle = dir.z;
    return v * cos_angle + glm::cross(k, v) * sin_angle + k * glm::dot(k, v) * (1.0 - cos_angle);
}

// The stalk from its kit (built upright at the origin when the scene loaded): turned to `dir` and moved to
// `base`, its components moved in (their storage and the stalk's list of children have room: nothing is
// allocated).
ecs::Entity stalk_from(ecs::Registry& r, StalkKit& kit, glm::dvec3 base, glm::dvec3 dir) {
    for (auto& x : kit.points.position_m) x = base + turned_from_up(x, dir);
    for (auto* list : {&kit.frame.director, &kit.frame.segment_direction, &kit.frame.held_director, &kit.frame.held_at}) {
        for (auto& d : *list) d = turned_from_up(d, dir);
    }
    const ecs::Entity e = r.create();
    r.emplace<StemPoints>(e, std::move(kit.points));
    r.emplace<StemRestShape>(e, std::move(kit.rest));
    r.emplace<StemSprings>(e, std::move(kit.springs));
    r.emplace<StemFrame>(e, std::move(kit.frame));
    r.emplace<StemLoads>(e, std::move(kit.loads));
    r.emplace<Cutting>(e, std::move(kit.cutting));
    if (kit.look) r.emplace<FlowerLook>(e, std::move(*kit.look));
    r.emplace<ecs::Children>(e, std::move(kit.children));
    kit.used = true;
    return e;
}

void prune(ecs::Registry& r, const Found& found, StructureReserve* reserve) {
    // What it keeps of its flower (its species, its look) comes from its kit; a flower without one (added
    // after the scene loaded) has them copied here.
    const auto copy_species = [&] { return r.all_of<Flower>(found.flower) ? r.get<const Flower>(found.flower).species : std::string{}; };
    const auto copy_look = [&] {
        const auto* look = r.try_get<const FlowerLook>(found.flower);
        return look ? std::optional<FlowerLook>(*look) : std::nullopt;
    };
    if (!found.twig.is_null()) {
        // Off at its fork: it and its own twigs leave the flower's list; it keeps them as a loose branch
        // (the list is in order, every twig after the one it grows from).
        LooseBranchKit* kit = reserve ? reserve->branch_for(found.twig) : nullptr;
        Twigs own;
        auto& going = kit ? kit->twigs.entities : own.entities;
        going.clear();
        auto& list = r.get<Twigs>(found.flower).entities;
        const auto is_going = [&](ecs::Entity t) { return std::find(going.begin(), going.end(), t) != going.end(); };
        for (const ecs::Entity t : list) {
            const auto* fork = r.try_get<StemFork>(t);
            if (fork && (fork->parent == found.twig || is_going(fork->parent))) going.push_back(t);
        }
        std::erase_if(list, [&](ecs::Entity t) { return t == found.twig || is_going(t); });
        if (list.empty()) r.remove<Twigs>(found.flower);
        r.remove<StemFork>(found.twig);
        if (!going.empty()) r.emplace<Twigs>(found.twig, std::move(kit ? kit->twigs : own));
        if (kit) {
            r.emplace<Cutting>(found.twig, std::move(kit->cutting));
            if (kit->look) r.emplace<FlowerLook>(found.twig, std::move(*kit->look));
            kit->used = true;
        } else {
            r.emplace<Cutting>(found.twig, Cutting{copy_species()});
            if (auto look = copy_look()) r.emplace<FlowerLook>(found.twig, std::move(*look));
        }
        return;
    }
    // A leaf or blossom stripped: it falls on a short stalk of its own (10 mm from where it grew).
    Part moved = std::move(r.get<Part>(found.part)); // its mesh's name moved, not copied
    const auto& points = r.get<StemPoints>(found.owner);
    const auto* frame = r.try_get<StemFrame>(found.owner);
    const glm::dvec3 middle = part_middle(moved, points, frame);
    const glm::dvec3 base = points.position_m[std::min<std::size_t>(moved.stem_point, points.position_m.size() - 1)];
    const glm::dvec3 out = middle - base;
    const double size = glm::length(out);
    const glm::dvec3 dir = size > 1e-9 ? out / size : glm::dvec3{0.0, 0.0, 1.0};
    StalkKit* kit = reserve ? reserve->stalk_for(found.part) : nullptr;
    const ecs::Entity stalk = kit ? stalk_from(r, *kit, base, dir) : [&] {
        const auto look = copy_look();
        return loose_stem(r, {base, base + 0.5 * stalk_length_m * dir, base + stalk_length_m * dir}, 0.001, 0.0002, copy_species(), look ? &*look : nullptr);
    }();
    moved.stem_point = 0;
    moved.offset_m = glm::dvec3{0.0, 0.0, size}; // along its stalk, as long as it was
    r.destroy(found.part);
    const ecs::Entity leaf = r.create(); // in the slot the part left
    r.emplace<Part>(leaf, std::move(moved));
    r.emplace<Collider>(leaf, ShapeKind::sphere, glm::dvec3{0.0}, glm::dvec3{0.0}, 0.3 * size, glm::dvec3{0.0});
    r.emplace<InactiveCollider>(leaf);
    ecs::attach(r, leaf, stalk);
}

} // namespace

void PruningSystem::operator()(sched::SystemContext& ctx) {
    auto& r = ctx.registry;
    pending_count_ = 0;
    StructureReserve* reserve = r.resource<StructureReserve>(); // the kits, for the change queued below
    r.view<const HandCube, const HandProxy, const PruneRequest>().each([&](ecs::Entity hand, const HandCube& cube, const HandProxy& proxy, const PruneRequest&) {
        r.commands().remove<PruneRequest>(hand);
        const glm::dvec3 at = proxy.position_m;
        const double reach = 0.5 * cube.edge_m;
        Found found;
        r.view<const Flower, const Twigs>().each([&](ecs::Entity flower, const Flower&, const Twigs& twigs) {
            for (const ecs::Entity twig : twigs.entities) {
                const auto* points = r.try_get<const StemPoints>(twig);
                const auto* rest = r.try_get<const StemRestShape>(twig);
                if (!points || !rest) continue;
                const auto& x = points->position_m;
                for (std::size_t i = 1; i < x.size(); ++i) {
                    const double d = to_segment(at, x[i - 1], x[i]) - 0.5 * rest->diameter_m;
                    if (d <= reach && d < found.distance_m) found = {std::max(d, 0.0), flower, twig, ecs::null_entity, ecs::null_entity};
                }
                consider_parts(r, flower, twig, at, reach, found);
            }
        });
        r.view<const Flower, const StemPoints>().each([&](ecs::Entity flower, const Flower&, const StemPoints&) { consider_parts(r, flower, flower, at, reach, found); });
        if (!found.flower.is_null() && pending_count_ < pending_.size()) pending_[pending_count_++] = found;
    });
    if (pending_count_ == 0) return;
    // After the views: pruning changes what they iterate. The queued operation holds two pointers (within
    // std::function's own buffer: queuing it allocates nothing).
    r.commands().defer([this, reserve](ecs::Registry& reg) {
        for (std::size_t i = 0; i < pending_count_; ++i) prune(reg, pending_[i], reserve);
        pending_count_ = 0;
    });
}

glm::dvec3 part_middle(const Part& part, const StemPoints& points, const StemFrame* frame) {
    const auto& x = points.position_m;
    const std::size_t at = std::min<std::size_t>(part.stem_point, x.size() - 1);
    // (Not `frame ? frame->director : {}`: that copies the directors, a heap allocation a part.)
    const auto f = frame ? physics::attachment_frame(x, at, frame->director) : physics::attachment_frame(x, at);
    return f.place(part.offset_m);
}

} // namespace ikebana::systems
