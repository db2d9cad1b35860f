#include "systems/presentation/receive_frame_system.hpp"

#include "engine/ecs/registry.hpp"
#include "systems/presentation/frame_channel.hpp"

namespace ikebana::systems {

void ReceiveFrameSystem::operator()(sched::SystemContext& ctx) {
    auto** channel = ctx.registry.resource<FrameChannel*>();
    auto* received = ctx.registry.resource<ReceivedFrames>();
    if (!channel || !*channel || !received) return;
    ++received->frames;
    if ((*channel)->buffer.update()) {
        ++received->fresh;
        received->latest = (*channel)->buffer.read_buffer();
    }
}

} // namespace ikebana::systems
