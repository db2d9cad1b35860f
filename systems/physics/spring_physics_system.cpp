#include "systems/physics/spring_physics_system.hpp"

#include <algorithm>

#include "engine/ecs/registry.hpp"

namespace ikebana::systems {

void SpringPhysicsSystem::operator()(sched::SystemContext& ctx) {
    auto& registry = ctx.registry;
    const auto* settings = registry.resource<const components::PhysicsSettings>();
    const glm::dvec3 gravity = settings ? settings->gravity_m_s2 : components::PhysicsSettings{}.gravity_m_s2;
    registry.view<components::StemPoints, const components::StemRestShape, const components::StemSprings, components::StemLoads>().each(
        [&](ecs::Entity e, components::StemPoints& points, const components::StemRestShape& rest,
            const components::StemSprings& springs, components::StemLoads& loads) {
            const auto* clamp = registry.try_get<const components::StemClamp>(e);
            // A stiff stem's tick in equal parts (see stable_substeps); the others' external forces act
            // through all of them. The last part's end forces are what a hand feels.
            const std::size_t parts = physics::stable_substeps(points, rest, springs, clamp, ctx.dt_s);
            const bool held = std::any_of(points.pinned.begin(), points.pinned.end(), [](std::uint8_t p) { return p != 0; });
            bool finite = true;
            for (std::size_t part = 0; part < parts && finite; ++part) {
                scratch.want_end_force = held && part + 1 == parts; // only a held stem's last part is felt
                finite = physics::step_stem(points, rest, springs, clamp, gravity, ctx.dt_s / static_cast<double>(parts), scratch);
            }
            if (finite) {
                // The stem's own forces of this step (springs, hinges, clamp, gravity: without what other
                // systems pushed), for whatever else needs them (a hand that holds the stem): computed once
                // a tick, here.
                loads.force_n.resize(scratch.end_force.size());
                for (std::size_t i = 0; i < scratch.end_force.size(); ++i) loads.force_n[i] = scratch.end_force[i] - points.external_force_n[i];
            } else {
                // A non-finite step is refused: the stem stays where it was, at rest, rather than
                // carrying NaN into contacts and force output.
                ++failed_steps;
                for (auto& v : points.velocity_m_s) v = glm::dvec3{0.0};
                loads.force_n.assign(points.position_m.size(), glm::dvec3{0.0});
            }
            for (auto& f : points.external_force_n) f = glm::dvec3{0.0};
        });
}

} // namespace ikebana::systems
