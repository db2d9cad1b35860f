#include "systems/collision/spread_collision_system.hpp"

#include "engine/ecs/registry.hpp"

namespace ikebana::systems {

void SpreadCollisionSystem::operator()(sched::SystemContext& ctx) {
    auto& r = ctx.registry;
    const auto* update = r.resource<const components::ColliderPass>();
    if (step < 0) {
        // A pass starts after an update (whose own tick carries the update) and is finished before the
        // next starts: with updates faster than a pass takes (--rate), passes run back to back on the
        // latest colliders rather than restarting for ever.
        if (!update || update->generation == seen_generation) return;
        seen_generation = update->generation;
        step = 0;
        return;
    }
    const auto g = static_cast<std::int64_t>(gather_slices);
    const auto n = static_cast<std::int64_t>(slices);
    if (step == 0) pass.begin(r);
    else if (step <= g) pass.gather(static_cast<std::size_t>(step - 1), gather_slices);
    else if (step <= g + n) pass.query(static_cast<std::size_t>(step - g - 1), slices);
    else {
        pass.query_pins(r);
        pass.publish(r);
        step = -1;
        return;
    }
    ++step;
}

} // namespace ikebana::systems
