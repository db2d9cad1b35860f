#include "systems/haptics/haptics_module.hpp"

#include "engine/sched/schedule.hpp"
#include "systems/haptics/bending_system.hpp"
#include "systems/haptics/grab_system.hpp"
#include "systems/haptics/hand_force_system.hpp"
#include "systems/haptics/hand_input_system.hpp"
#include "systems/haptics/trainee_command_system.hpp"
#include "systems/haptics/workspace_view_system.hpp"

namespace ikebana::systems {

Result<void> install_haptics(sched::Schedule& s, ForceScheme scheme) {
    using sched::describe;
    s.begin_module("haptics");
    std::vector<sched::SystemDesc> descs{describe(WorkspaceViewSystem{}),
                                         describe(HandInputSystem{}, {std::string(WorkspaceViewSystem::name)}),
                                         describe(GrabSystem{}, {std::string(HandInputSystem::name)}),
                                         describe(BendingSystem{}, {std::string(GrabSystem::name)}),
                                         describe(TraineeCommandSystem{}, {std::string(BendingSystem::name)})};
    if (scheme == ForceScheme::paper) {
        descs.push_back(describe(ForceCheckSystem{}));
        descs.push_back(describe(ForceEstimateSystem{}, {std::string(ForceCheckSystem::name)}));
        descs.push_back(describe(ForceOutputSystem{}, {std::string(ForceEstimateSystem::name)}));
    } else {
        descs.push_back(describe(HandForceSystem{}));
    }
    for (auto& desc : descs) {
        if (auto r = s.add(std::move(desc)); !r) return r;
    }
    s.end_module();
    return {};
}

} // namespace ikebana::systems
