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
struct Found {
    double distance_m = std::numeric_limits<double>::infinity();
    ecs::Entity flower = ecs::null_entity; // whose Twigs list it is on
    ecs::Entity twig = ecs::null_entity;   // a twig to cut off at its fork
    ecs::Entity part = ecs::null_entity;   // or a leaf or blossom to strip
    ecs::Entity owner = ecs::null_entity;  // the stem or twig the part grows on
};

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

void prune(ecs::Registry& r, const Found& found) {
    const std::string species = r.all_of<Flower>(found.flower) ? r.get<const Flower>(found.flower).species : std::string{};
    const auto* found_look = r.try_get<const FlowerLook>(found.flower);
    const std::optional<FlowerLook> look_copy = found_look ? std::optional<FlowerLook>(*found_look) : std::nullopt; // emplacing may move it
    const FlowerLook* look = look_copy ? &*look_copy : nullptr;
    if (!found.twig.is_null()) {
        // Off at its fork: it and its own twigs leave the flower's list; it keeps them as a loose branch.
        auto& list = r.get<Twigs>(found.flower).entities;
        std::vector<ecs::Entity> going{found.twig};
        for (const ecs::Entity t : list) {
            const auto* fork = r.try_get<StemFork>(t);
            if (fork && std::find(going.begin(), going.end(), fork->parent) != going.end()) going.push_back(t);
        }
        std::erase_if(list, [&](ecs::Entity t) { return std::find(going.begin(), going.end(), t) != going.end(); });
        if (list.empty()) r.remove<Twigs>(found.flower);
        r.remove<StemFork>(found.twig);
        if (going.size() > 1) r.emplace<Twigs>(found.twig, Twigs{std::vector<ecs::Entity>(going.begin() + 1, going.end())});
        r.emplace<Cutting>(found.twig, Cutting{species});
        if (look) r.emplace<FlowerLook>(found.twig, *look);
        return;
    }
    // A leaf or blossom stripped: it falls on a short stalk of its own (10 mm from where it grew).
    const Part part = r.get<Part>(found.part);
    const auto& points = r.get<StemPoints>(found.owner);
    const auto* frame = r.try_get<StemFrame>(found.owner);
    const glm::dvec3 middle = part_middle(part, points, frame);
    const glm::dvec3 base = points.position_m[std::min<std::size_t>(part.stem_point, points.position_m.size() - 1)];
    const glm::dvec3 out = middle - base;
    const double size = glm::length(out);
    const glm::dvec3 dir = size > 1e-9 ? out / size : glm::dvec3{0.0, 0.0, 1.0};
    const ecs::Entity stalk = loose_stem(r, {base, base + 0.005 * dir, base + 0.01 * dir}, 0.001, 0.0002, species, look);
    Part moved = part;
    moved.stem_point = 0;
    moved.offset_m = glm::dvec3{0.0, 0.0, size}; // along its stalk, as long as it was
    r.destroy(found.part);
    const ecs::Entity leaf = r.create();
    r.emplace<Part>(leaf, moved);
    r.emplace<Collider>(leaf, ShapeKind::sphere, glm::dvec3{0.0}, glm::dvec3{0.0}, 0.3 * size, glm::dvec3{0.0});
    r.emplace<InactiveCollider>(leaf);
    ecs::attach(r, leaf, stalk);
}

} // namespace

void PruningSystem::operator()(sched::SystemContext& ctx) {
    auto& r = ctx.registry;
    std::vector<Found> cuts;
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
        if (!found.flower.is_null()) cuts.push_back(found);
    });
    // After the views: pruning changes what they iterate.
    for (const Found& found : cuts) r.commands().defer([found](ecs::Registry& reg) { prune(reg, found); });
}

glm::dvec3 part_middle(const Part& part, const StemPoints& points, const StemFrame* frame) {
    const auto& x = points.position_m;
    const auto f = physics::attachment_frame(x, std::min<std::size_t>(part.stem_point, x.size() - 1), frame ? frame->director : std::vector<glm::dvec3>{});
    return f.place(part.offset_m);
}

} // namespace ikebana::systems
