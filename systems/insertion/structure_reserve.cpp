#include "systems/insertion/structure_reserve.hpp"

#include <algorithm>
#include <functional>

#include "components/collision.hpp"
#include "components/flower.hpp"
#include "components/physics.hpp"
#include "engine/ecs/registry.hpp"
#include "systems/physics/stem_builder.hpp"

namespace ikebana::systems {

using namespace components;

namespace {

bool by_entity(ecs::Entity a, ecs::Entity b) { return a.index != b.index ? a.index < b.index : a.generation < b.generation; }

template <typename Kit>
Kit* find_kit(std::vector<Kit>& kits, ecs::Entity e, ecs::Entity Kit::*key) {
    const auto it = std::lower_bound(kits.begin(), kits.end(), e, [&](const Kit& k, ecs::Entity x) { return by_entity(k.*key, x); });
    return it != kits.end() && (*it).*key == e && !it->used ? &*it : nullptr;
}

StalkKit stalk_kit(ecs::Entity part, const std::string& species, const std::optional<FlowerLook>& look) {
    physics::StemSpec spec;
    spec.segments = 2;
    spec.length_m = stalk_length_m;
    spec.diameter_m = 0.001;
    spec.youngs_modulus_pa = 5.0e7;
    spec.stem_mass_kg = 0.0002;
    spec.base_m = glm::dvec3{0.0};
    spec.direction = glm::dvec3{0.0, 0.0, 1.0};
    auto built = physics::build_stem(spec);
    StalkKit kit{part, std::move(built.points), std::move(built.rest), std::move(built.springs), std::move(built.frame), {}, Cutting{species}, look, {}, false};
    kit.loads.force_n.assign(kit.points.position_m.size(), glm::dvec3{0.0});
    kit.children.entities.reserve(1);
    return kit;
}

void add_stalks_of(ecs::Registry& r, ecs::Entity owner, const std::string& species, const std::optional<FlowerLook>& look, StructureReserve& out) {
    const auto* children = r.try_get<const ecs::Children>(owner);
    if (!children) return;
    for (const ecs::Entity child : children->entities) {
        const auto* part = r.try_get<const Part>(child);
        if (part && part->kind != PartKind::stem && !part->mesh.empty()) out.stalks.push_back(stalk_kit(child, species, look));
    }
}

// The bodies now and every piece the kits can make, each counted at its largest.
BodyCapacity body_capacity(ecs::Registry& r, const StructureReserve& reserve) {
    BodyCapacity c;
    r.view<const StemPoints>().each([&](ecs::Entity e, const StemPoints& points) {
        c.points = std::max(c.points, points.position_m.size());
        if (r.all_of<StemFork>(e)) return; // a twig is its stem's body
        ++c.bodies;
        c.stem_points.push_back(points.position_m.size()); // a tree whose twigs are all pruned is a stem
        const auto* twigs = r.try_get<const Twigs>(e);
        if (!twigs || twigs->entities.empty()) return;
        ++c.trees;
        std::size_t nodes = points.position_m.size();
        for (const ecs::Entity t : twigs->entities) {
            if (const auto* p = r.try_get<const StemPoints>(t)) nodes += p->position_m.size();
        }
        c.tree_chains = std::max(c.tree_chains, 1 + twigs->entities.size());
        c.tree_nodes = std::max(c.tree_nodes, nodes);
    });
    // A twig pruned with twigs of its own is a tree; without, a stem. A stalk is a stem.
    std::vector<ecs::Entity> parents;
    r.view<const StemFork>().each([&](ecs::Entity, const StemFork& fork) { parents.push_back(fork.parent); });
    std::sort(parents.begin(), parents.end(), by_entity);
    for (const auto& kit : reserve.branches) {
        ++c.bodies;
        if (const auto* p = r.try_get<const StemPoints>(kit.twig)) c.stem_points.push_back(p->position_m.size());
        c.trees += std::binary_search(parents.begin(), parents.end(), kit.twig, by_entity) ? 1 : 0;
    }
    c.bodies += reserve.stalks.size();
    for (const auto& stalk : reserve.stalks) c.stem_points.push_back(stalk.points.position_m.size());
    std::sort(c.stem_points.begin(), c.stem_points.end(), std::greater<>());
    if (!reserve.stalks.empty()) c.points = std::max(c.points, reserve.stalks.front().points.position_m.size());
    c.cuttings = reserve.branches.size() + reserve.stalks.size();
    c.stalks = reserve.stalks.size();
    c.stalk_points = reserve.stalks.empty() ? 0 : reserve.stalks.front().points.position_m.size();
    c.pieces = c.cuttings;
    r.view<const FlowerLook>().each([&](ecs::Entity, const FlowerLook& look) { c.mesh_name = std::max(c.mesh_name, look.head_mesh.size()); });
    r.view<const ecs::Children>().each([&](ecs::Entity, const ecs::Children& children) {
        std::size_t drawn = 0;
        for (const ecs::Entity child : children.entities) {
            const auto* part = r.try_get<const Part>(child);
            if (!part || part->kind == PartKind::stem || part->mesh.empty()) continue;
            ++drawn;
            c.mesh_name = std::max(c.mesh_name, part->mesh.size());
        }
        c.parts += drawn;
        c.piece_parts = std::max(c.piece_parts, drawn);
    });
    return c;
}

} // namespace

LooseBranchKit* StructureReserve::branch_for(ecs::Entity twig) { return find_kit(branches, twig, &LooseBranchKit::twig); }
StalkKit* StructureReserve::stalk_for(ecs::Entity part) { return find_kit(stalks, part, &StalkKit::part); }

void reserve_structure_changes(ecs::Registry& r) {
    StructureReserve out;
    auto& cut = out.cut;
    for (auto* v : {&cut.before, &cut.fresh, &cut.twig_moved}) v->reserve(std::max(most_stem_points, most_twigs));
    for (auto* v : {&cut.arc, &cut.at, &cut.curvature, &cut.angle}) v->reserve(most_stem_points);
    cut.direction.reserve(most_stem_points);
    cut.twig_gone.reserve(most_twigs);
    cut.kept.reserve(most_twigs);
    cut.gone.reserve(std::max(most_stem_points, most_twigs)); // parts on a stem, at most one a point and more
    r.view<const Flower>().each([&](ecs::Entity flower, const Flower& f) {
        const auto* found_look = r.try_get<const FlowerLook>(flower);
        const std::optional<FlowerLook> look = found_look ? std::optional<FlowerLook>(*found_look) : std::nullopt;
        add_stalks_of(r, flower, f.species, look, out);
        const auto* twigs = r.try_get<const Twigs>(flower);
        if (!twigs) return;
        for (std::size_t t = 0; t < twigs->entities.size(); ++t) {
            LooseBranchKit kit{twigs->entities[t], {}, Cutting{f.species}, look, false};
            kit.twigs.entities.reserve(twigs->entities.size() - t); // every twig listed after it, at most
            out.branches.push_back(std::move(kit));
            add_stalks_of(r, twigs->entities[t], f.species, look, out);
        }
    });
    std::sort(out.branches.begin(), out.branches.end(), [](const auto& a, const auto& b) { return by_entity(a.twig, b.twig); });
    std::sort(out.stalks.begin(), out.stalks.end(), [](const auto& a, const auto& b) { return by_entity(a.part, b.part); });
    // Room in the registry for what pruning adds: a stalk entity a part (the part itself is made anew in
    // the slot its old self leaves), the components a stalk, a stripped part and a loose branch get.
    const std::size_t stalks = out.stalks.size();
    const std::size_t loose = stalks + out.branches.size();
    r.reserve<StemPoints>(stalks);
    r.reserve<StemRestShape>(stalks);
    r.reserve<StemSprings>(stalks);
    r.reserve<StemFrame>(stalks);
    r.reserve<StemLoads>(stalks);
    r.reserve<ecs::Children>(stalks);
    r.reserve<ecs::ChildOf>(1);
    r.reserve<Part>(1);
    r.reserve<Collider>(stalks);
    r.reserve<InactiveCollider>(stalks);
    r.reserve<Cutting>(loose);
    r.reserve<FlowerLook>(loose);
    r.reserve<Twigs>(out.branches.size());
    r.reserve<CutRequest>(2); // a request a hand, their storage made now
    r.reserve<PruneRequest>(2);
    r.reserve_entities(stalks + 1);
    r.set_resource<BodyCapacity>(body_capacity(r, out));
    r.set_resource<StructureReserve>(std::move(out));
}

} // namespace ikebana::systems
