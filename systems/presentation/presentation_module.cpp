#include "systems/presentation/presentation_module.hpp"

#include "engine/sched/schedule.hpp"
#include "systems/presentation/prepare_frame_system.hpp"
#include "systems/presentation/publish_frame_system.hpp"
#include "systems/presentation/receive_frame_system.hpp"

namespace ikebana::systems {

Result<void> install_presentation(sched::Schedule& s) {
    using sched::describe;
    s.begin_module("presentation");
    for (auto desc : {describe(PublishFrameSystem{}), describe(ReceiveFrameSystem{}), describe(PrepareFrameSystem{})}) {
        if (auto r = s.add(std::move(desc)); !r) return r;
    }
    s.end_module();
    return {};
}

} // namespace ikebana::systems
