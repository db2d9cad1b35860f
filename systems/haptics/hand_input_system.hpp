#pragma once
// Reads each hand's device, maps it into the world, and moves the hand cube (the proxy) there as far
// as rigid things allow (the table top; the kenzan's base). A device that stops answering is marked
// disconnected (the grab system then lets go of what the hand held, and the force systems send it
// zero); the session goes on, and the hand picks up again when the device answers again.
#include <string_view>

#include "components/collision.hpp"
#include "components/hand.hpp"
#include "components/kenzan.hpp"
#include "components/physics.hpp"
#include "components/stem.hpp"
#include "engine/sched/system.hpp"
#include "systems/haptics/hand_devices.hpp"

namespace ikebana::systems {

// The fastest a hand's proxy moves while it holds a stem: a quick human hand, with room (about 2 m/s in
// a flick). A device or a script that jumps further in one tick (a scripted hand 1.3 m per tick once
// drove a held stem's energy to tens of kJ) is followed at this speed, and the gap is felt as a pull.
// A free hand goes where its device says (a script may place it on a stem at once).
inline constexpr double max_hand_speed_m_s = 5.0;

// A rate device's twist (normalised, [-1, 1]) below this turns nothing.
inline constexpr double rate_dead_zone = 0.05;

// A held stem's end this close above the plate (or the table) stands on it: the hand goes no lower.
inline constexpr double end_on_floor_m = 0.001;

struct HandInputSystem {
    static constexpr std::string_view name = "hand_input";
    static constexpr std::string_view lane = "sim";
    static constexpr std::string_view phase = "input";
    static constexpr std::string_view rate = "haptic";
    using reads = sched::Components<components::WorkspaceMapping, components::HandCube, components::HandGrip,
                                    components::Kenzan, components::Table, components::Container, components::StemPoints, components::StemRestShape>;
    // HandDevices: polling a device and recording its samples are writes (hand_devices.hpp).
    using writes = sched::Components<HandDevices, components::HandInput, components::HandProxy, components::Collider, HandLinks>;

    void operator()(sched::SystemContext& ctx);
};

} // namespace ikebana::systems
