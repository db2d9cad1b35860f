#include "systems/presentation/receive_frame_system.hpp"

#include "engine/ecs/registry.hpp"

namespace ikebana::systems {

void ReceiveFrameSystem::operator()(sched::SystemContext& ctx) {
    auto* port = ctx.registry.resource<ecs::Port<FrameChannel>>();
    auto* received = ctx.registry.resource<ReceivedFrames>();
    if (!port || !received) return;
    FrameChannel& channel = port->use();
    ++received->frames;
    if (!channel.buffer.update()) return; // nothing new: the current snapshot stays
    const bool first = received->current == nullptr;
    received->current = &channel.buffer.read_buffer();
    ++received->fresh;
    const auto& now_hands = received->current->hands;
    if (received->announce && !first) {
        for (int h = 0; h < 2; ++h) {
            const auto& was = received->previous_hands[h];
            const auto& now = now_hands[h];
            if (!now.present) continue;
            const char* hand_name = h ? "right" : "left";
            if (now.disconnects > was.disconnects) {
                received->announce(std::string(hand_name) + " hand: device unplugged; what it held is released and its force is zero");
            } else if (now.connected && !was.connected && now.disconnects > 0) {
                received->announce(std::string(hand_name) + " hand: device back; the hand follows it again");
            }
        }
    }
    for (int h = 0; h < 2; ++h) received->previous_hands[h] = now_hands[h];
}

} // namespace ikebana::systems
