#include "systems/physics/spring_physics_system.hpp"

#include "engine/ecs/registry.hpp"

namespace ikebana::systems {

void SpringPhysicsSystem::operator()(sched::SystemContext& ctx) {
    auto& registry = ctx.registry;
    const auto* settings = registry.resource<components::PhysicsSettings>();
    const glm::dvec3 gravity = settings ? settings->gravity_m_s2 : components::PhysicsSettings{}.gravity_m_s2;
    registry.view<components::StemPoints, components::StemRestShape, components::StemSprings>().each(
        [&](ecs::Entity e, components::StemPoints& points, components::StemRestShape& rest,
            components::StemSprings& springs) {
            const auto* clamp = registry.try_get<components::StemClamp>(e);
            if (!physics::step_stem(points, rest, springs, clamp, gravity, ctx.dt_s, scratch)) {
                // A non-finite step is refused: the stem stays where it was, at rest, rather than
                // carrying NaN into contacts and force output.
                ++failed_steps;
                for (auto& v : points.velocity_m_s) v = glm::dvec3{0.0};
            }
            for (auto& f : points.external_force_n) f = glm::dvec3{0.0};
        });
}

} // namespace ikebana::systems
