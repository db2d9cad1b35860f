#pragma once
// Reads each hand's device, maps it into the world, and moves the hand cube (the proxy) there as far
// as rigid things allow (the table top; the kenzan's base). A device that stops answering releases
// what its hand held, zeroes its force and is marked disconnected; the session goes on, and the hand
// picks up again when the device answers again.
#include <string_view>

#include "components/collision.hpp"
#include "components/hand.hpp"
#include "components/insertion.hpp"
#include "components/stem.hpp"
#include "engine/sched/system.hpp"

namespace ikebana::systems {

struct HandInputSystem {
    static constexpr std::string_view name = "hand_input";
    static constexpr std::string_view lane = "sim";
    static constexpr std::string_view phase = "input";
    static constexpr std::string_view rate = "haptic";
    using reads = sched::Components<components::WorkspaceMapping, components::HandCube>;
    using writes = sched::Components<components::HandState, components::Collider, components::StemPoints, components::Grasp>;

    void operator()(sched::SystemContext& ctx);
};

// Lets go of whatever `hand` holds (used on release and on disconnect).
void release_hold(ecs::Registry& registry, components::HandState& hand);

// Lets go of the second point of a one-hand grip (a second hand took the flower, or the hand lets go);
// the held point stays held.
void let_go_of_direction(ecs::Registry& registry, components::HandState& hand);

} // namespace ikebana::systems
