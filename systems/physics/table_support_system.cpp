#include "systems/physics/table_support_system.hpp"

#include <cmath>

#include "engine/ecs/registry.hpp"

namespace ikebana::systems {

void TableSupportSystem::operator()(sched::SystemContext& ctx) {
    const auto* table = ctx.registry.resource<const components::Table>();
    if (!table) return;
    const auto* settings = ctx.registry.resource<const components::PhysicsSettings>();
    const double g = settings ? std::abs(settings->gravity_m_s2.z) : 9.80665;
    ctx.registry.view<components::StemPoints, const components::StemRestShape>().each(
        [&](ecs::Entity, components::StemPoints& points, const components::StemRestShape& rest) {
            const double floor = table->height_m + 0.5 * rest.diameter_m;
            for (std::size_t i = 0; i < points.position_m.size(); ++i) {
                auto& x = points.position_m[i];
                auto& v = points.velocity_m_s[i];
                if (x.z >= floor) continue;
                x.z = floor;
                if (v.z < 0.0) v.z = 0.0;
                // Friction removes at most mu * g * dt of sliding speed per tick.
                const glm::dvec2 slide{v.x, v.y};
                const double speed = glm::length(slide);
                const double loss = table->friction * g * ctx.dt_s;
                const glm::dvec2 kept = speed > loss ? slide * (1.0 - loss / speed) : glm::dvec2{0.0};
                v.x = kept.x;
                v.y = kept.y;
            }
        });
}

} // namespace ikebana::systems
