#pragma once
// Main lane, first: takes the newest simulation snapshot (in place, no copy), and announces devices
// unplugged or back.
#include <string_view>

#include "engine/ecs/port.hpp"
#include "engine/sched/system.hpp"
#include "systems/presentation/frame_channel.hpp"

namespace ikebana::systems {

struct ReceiveFrameSystem {
    static constexpr std::string_view name = "receive_frame";
    static constexpr std::string_view lane = "main";
    static constexpr std::string_view phase = "receive";
    static constexpr std::string_view rate = "render";
    using reads = sched::Components<>;
    using writes = sched::Components<ecs::Port<FrameChannel>, ReceivedFrames>; // receiving swaps the channel's buffers

    void operator()(sched::SystemContext& ctx);
};

} // namespace ikebana::systems
