#pragma once
// Extract: copies the plain state the main thread needs to show the world (stems, looks, parts, the
// kenzan, the table, the hands, how each flower stands) into the frame channel, at the render rate.
// Nothing is drawn here: the main lane prepares the draw list and the HUD (prepare_frame_system).
#include <string_view>
#include <utility>
#include <vector>

#include "components/appearance.hpp"
#include "components/collision.hpp"
#include "components/flower.hpp"
#include "components/hand.hpp"
#include "components/insertion.hpp"
#include "components/kenzan.hpp"
#include "components/physics.hpp"
#include "components/stem.hpp"
#include "engine/ecs/port.hpp"
#include "engine/sched/system.hpp"
#include "systems/haptics/hand_devices.hpp"
#include "systems/presentation/frame_channel.hpp"

namespace ikebana::systems {

struct PublishFrameSystem {
    static constexpr std::string_view name = "publish_frame";
    static constexpr std::string_view lane = "sim";
    static constexpr std::string_view phase = "present"; // after every system that writes what it copies
    static constexpr std::string_view rate = "render";
    using reads = sched::Components<components::StemPoints, components::StemRestShape, components::StemFrame, components::Twigs, components::Cutting, components::Flower,
                                    components::FlowerLook, components::Part, ecs::Children, components::Contacts,
                                    components::HandCube, components::HandInput, components::HandProxy, components::HandGrip,
                                    components::HandForce, components::InsertionHistory, components::PinEngagement,
                                    components::KenzanGrip, components::Kenzan, components::Table, components::Container,
                                    HandDevices, HandLinks, components::BodyCapacity>;
    using writes = sched::Components<ecs::Port<FrameChannel>>; // publishing is a write of the channel

    void operator()(sched::SystemContext& ctx);
};

} // namespace ikebana::systems
