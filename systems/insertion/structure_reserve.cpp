#include "systems/insertion/structure_reserve.hpp"

#include <algorithm>

#include "components/collision.hpp"
#include "components/flower.hpp"
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
    r.set_resource<StructureReserve>(std::move(out));
}

} // namespace ikebana::systems
