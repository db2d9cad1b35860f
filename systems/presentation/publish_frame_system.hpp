#pragma once
// Copies what the main thread needs to draw into the frame channel, at the render rate.
#include <string_view>

#include "components/collision.hpp"
#include "components/flower.hpp"
#include "components/hand.hpp"
#include "components/insertion.hpp"
#include "components/stem.hpp"
#include "engine/render/draw_list.hpp"
#include "engine/sched/system.hpp"
#include "systems/presentation/frame_channel.hpp"

namespace ikebana::systems {

struct PublishFrameSystem {
    static constexpr std::string_view name = "publish_frame";
    static constexpr std::string_view lane = "sim";
    static constexpr std::string_view phase = "present"; // after every system that writes what it copies
    static constexpr std::string_view rate = "render";
    using reads = sched::Components<FrameChannel*, components::StemPoints, components::Flower, components::Contacts,
                                    components::HandCube, components::HandInput, components::HandGrip, components::HandForce,
                                    components::InsertionHistory, components::PinEngagement, components::KenzanGrip,
                                    render::DrawList>;
    using writes = sched::Components<>;

    void operator()(sched::SystemContext& ctx);
};

} // namespace ikebana::systems
