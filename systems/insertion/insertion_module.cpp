#include "systems/insertion/insertion_module.hpp"

#include "engine/sched/schedule.hpp"
#include "systems/insertion/insertion_resistance_system.hpp"
#include "systems/insertion/insertion_tracking_system.hpp"
#include "systems/insertion/kenzan_grip_system.hpp"
#include "systems/insertion/pruning_system.hpp"
#include "systems/insertion/scripted_insertion_system.hpp"
#include "systems/insertion/stem_cutting_system.hpp"

namespace ikebana::systems {

Result<void> install_insertion(sched::Schedule& s) {
    using sched::describe;
    s.begin_module("insertion");
    for (auto desc : {describe(StemCuttingSystem{}), describe(PruningSystem{}, {std::string(StemCuttingSystem::name)}),
                      describe(ScriptedInsertionSystem{}, {std::string(PruningSystem::name)}),
                      describe(InsertionTrackingSystem{}),
                      describe(InsertionResistanceSystem{}, {std::string(InsertionTrackingSystem::name)}),
                      describe(KenzanGripSystem{}, {std::string(InsertionResistanceSystem::name)})}) {
        if (auto r = s.add(std::move(desc)); !r) return r;
    }
    s.end_module();
    return {};
}

} // namespace ikebana::systems
