#include "systems/collision/spread_collision_system.hpp"

#include "engine/ecs/registry.hpp"

namespace ikebana::systems {

void SpreadCollisionSystem::operator()(sched::SystemContext& ctx) {
    auto& r = ctx.registry;
    const auto* update = r.resource<const components::ColliderPass>();
    auto& pass = collision_pass::of(r);
    auto& step = pass.step;
    if (step < 0) {
        // A pass starts after an update (whose own tick carries the update) and is finished before the
        // next starts: with updates faster than a pass takes (--rate), passes run back to back on the
        // latest colliders rather than restarting for ever.
        if (!update || update->generation == pass.seen_generation) return;
        pass.seen_generation = update->generation;
        step = 0;
        return;
    }
    const auto g = static_cast<std::int64_t>(gather_slices);
    const auto n = static_cast<std::int64_t>(slices);
    if (step == 0) collision_pass::begin(r, pass);
    else if (step <= g) collision_pass::gather(pass, static_cast<std::size_t>(step - 1), gather_slices);
    else if (step <= g + n) collision_pass::query(pass, static_cast<std::size_t>(step - g - 1), slices);
    else {
        collision_pass::query_pins(r, pass);
        collision_pass::publish(r, pass);
        step = -1;
        return;
    }
    ++step;
}

} // namespace ikebana::systems
