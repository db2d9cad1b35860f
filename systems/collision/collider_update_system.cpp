#include "systems/collision/collider_update_system.hpp"

#include "engine/ecs/registry.hpp"

namespace ikebana::systems {

using namespace components;

void ColliderUpdateSystem::operator()(sched::SystemContext& ctx) {
    auto& r = ctx.registry;
    auto place = [&](ecs::Entity, Part& part, Collider& collider, ecs::ChildOf& owner) {
            const auto* stem = r.try_get<StemPoints>(owner.parent);
            if (!stem || stem->position_m.empty()) return;
            const auto& x = stem->position_m;
            const std::size_t i = std::min<std::size_t>(part.stem_point, x.size() - 1);
            if (part.kind == PartKind::stem && i + 1 < x.size()) {
                collider.a_m = x[i];
                collider.b_m = x[i + 1];
            } else {
                // Attached parts keep their offset in the frame of the stem's direction at that point.
                const glm::dvec3 along = i + 1 < x.size() ? x[i + 1] - x[i] : x[i] - x[i - 1];
                const glm::dvec3 up = glm::length(along) > 0.0 ? glm::normalize(along) : glm::dvec3{0, 0, 1};
                const glm::dvec3 side = std::abs(up.x) < 0.9 ? glm::normalize(glm::cross(up, glm::dvec3{1, 0, 0}))
                                                             : glm::normalize(glm::cross(up, glm::dvec3{0, 1, 0}));
                const glm::dvec3 third = glm::cross(up, side);
                collider.a_m = x[i] + part.offset_m.x * side + part.offset_m.y * third + part.offset_m.z * up;
                collider.b_m = collider.a_m;
            }
        };
    // Led by the tag storages, so Inactive parts are never visited, not even to be skipped.
    r.view<ActiveCollider, Part, Collider, ecs::ChildOf>().each(place);
    r.view<PassiveCollider, Part, Collider, ecs::ChildOf>().each(place);
}

} // namespace ikebana::systems
