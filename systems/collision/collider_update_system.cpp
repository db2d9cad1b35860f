#include "systems/collision/collider_update_system.hpp"

#include "engine/ecs/registry.hpp"
#include "systems/physics/part_attachment.hpp"

namespace ikebana::systems {

using namespace components;

void ColliderUpdateSystem::operator()(sched::SystemContext& ctx) {
    auto& r = ctx.registry;
    // A flower's parts come one after another, most of them on its head's point: the owner's stem and
    // the last frame are kept rather than looked up and built again for every petal.
    ecs::Entity last_owner{};
    const StemPoints* stem = nullptr;
    const std::vector<glm::dvec3> no_directors;
    const std::vector<glm::dvec3>* directors = &no_directors;
    const StemPoints* frame_stem = nullptr;
    std::size_t frame_point = 0;
    physics::AttachmentFrame frame{};
    auto place = [&](ecs::Entity, const Part& part, Collider& collider, const ecs::ChildOf& owner) {
        if (stem == nullptr || owner.parent != last_owner) {
            last_owner = owner.parent;
            stem = r.try_get<const StemPoints>(owner.parent);
            const auto* bark = r.try_get<const StemFrame>(owner.parent);
            directors = bark ? &bark->director : &no_directors;
        }
        if (!stem || stem->position_m.empty()) return;
        const auto& x = stem->position_m;
        const std::size_t i = std::min<std::size_t>(part.stem_point, x.size() - 1);
        if (part.kind == PartKind::stem && i + 1 < x.size()) {
            collider.a_m = x[i];
            collider.b_m = x[i + 1];
        } else {
            if (frame_stem != stem || frame_point != i) {
                frame = physics::attachment_frame(x, i, *directors);
                frame_stem = stem;
                frame_point = i;
            }
            collider.a_m = frame.place(part.offset_m);
            collider.b_m = collider.a_m;
        }
    };
    // Led by the tag storages, so Inactive parts are never visited, not even to be skipped.
    r.view<const ActiveCollider, const Part, Collider, const ecs::ChildOf>().each(place);
    r.view<const PassiveCollider, const Part, Collider, const ecs::ChildOf>().each(place);
    auto* pass = r.resource<ColliderPass>();
    if (!pass) pass = &r.set_resource<ColliderPass>();
    ++pass->generation;
}

} // namespace ikebana::systems
