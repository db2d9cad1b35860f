#include "systems/collision/collision_module.hpp"

#include "engine/sched/schedule.hpp"
#include "systems/collision/collider_update_system.hpp"
#include "systems/collision/spread_collision_system.hpp"

namespace ikebana::systems {

Result<void> install_collision(sched::Schedule& s) {
    s.begin_module("collision");
    for (auto desc : {sched::describe(ColliderUpdateSystem{}),
                      sched::describe(SpreadCollisionSystem{}, {std::string(ColliderUpdateSystem::name)})}) {
        if (auto r = s.add(std::move(desc)); !r) return r;
    }
    s.end_module();
    return {};
}

} // namespace ikebana::systems
