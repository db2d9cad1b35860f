#include "systems/presentation/receive_frame_system.hpp"

#include "engine/ecs/registry.hpp"
#include "systems/presentation/frame_channel.hpp"

namespace ikebana::systems {

void ReceiveFrameSystem::operator()(sched::SystemContext& ctx) {
    auto* const* channel = ctx.registry.resource<FrameChannel* const>();
    auto* received = ctx.registry.resource<ReceivedFrames>();
    if (!channel || !*channel || !received) return;
    ++received->frames;
    if ((*channel)->buffer.update()) {
        const components::FrameSnapshot previous = received->latest;
        ++received->fresh;
        received->latest = (*channel)->buffer.read_buffer();
        if (received->announce && received->fresh > 1) {
            for (int h = 0; h < 2; ++h) {
                const auto& was = previous.hands[h];
                const auto& now = received->latest.hands[h];
                if (!now.present) continue;
                const char* hand_name = h ? "right" : "left";
                if (now.disconnects > was.disconnects) {
                    received->announce(std::string(hand_name) + " hand: device unplugged; what it held is released and its force is zero");
                } else if (now.connected && !was.connected && now.disconnects > 0) {
                    received->announce(std::string(hand_name) + " hand: device back; the hand follows it again");
                }
            }
        }
    }
}

} // namespace ikebana::systems
