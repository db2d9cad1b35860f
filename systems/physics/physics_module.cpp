#include "systems/physics/physics_module.hpp"

#include "engine/sched/schedule.hpp"
#include "systems/physics/spring_physics_system.hpp"
#include "systems/physics/stem_frame_system.hpp"
#include "systems/physics/table_support_system.hpp"

namespace ikebana::systems {

Result<void> install_physics(sched::Schedule& s) {
    s.begin_module("physics");
    for (auto desc : {sched::describe(SpringPhysicsSystem{}), sched::describe(TableSupportSystem{}),
                      sched::describe(StemFrameSystem{}, {std::string{TableSupportSystem::name}})}) {
        if (auto r = s.add(std::move(desc)); !r) return r;
    }
    s.end_module();
    return {};
}

} // namespace ikebana::systems
