#pragma once
// What each hand feels: the coupling spring between the device and the cube it drives (pressing on
// the table or the kenzan), plus the stem's pull on the point the hand holds (its weight, its bending,
// and, when both hands hold one flower, the stretch of the part between: equal and opposite on the
// two hands). The device's own safety chain clamps, rate-limits and ramps afterwards.
//
// Two schemes, chosen when the world is built:
//  - full rate: HandForceSystem computes the force every 1 kHz tick;
//  - the paper's (section 2.3): ForceCheckSystem computes it at 16 Hz (position check),
//    ForceEstimateSystem extrapolates it at 100 Hz from the last two checks (the moving vector),
//    and ForceOutputSystem sends the same estimate ten times at 1 kHz.
#include <string_view>

#include "components/hand.hpp"
#include "components/physics.hpp"
#include "components/stem.hpp"
#include "engine/sched/system.hpp"
#include "systems/haptics/hand_devices.hpp"

namespace ikebana::systems {

// The force a hand feels now, from the live state (shared by both schemes): the coupling spring (its
// device's), and the loads the physics computed this tick on the points the grip holds (never computed
// again here).
glm::dvec3 hand_feels(ecs::Registry& registry, const components::HandCube& cube, const components::HandInput& input,
                      const components::HandProxy& proxy, const components::HandGrip& grip);

// Everything hand_feels reads.
using HandFeelsReads = sched::Components<HandCoupling, components::HandCube, components::HandInput, components::HandProxy,
                                         components::HandGrip, components::StemLoads, components::Bending>;

struct HandForceSystem {
    static constexpr std::string_view name = "hand_force";
    static constexpr std::string_view lane = "sim";
    static constexpr std::string_view phase = "output";
    static constexpr std::string_view rate = "haptic";
    using reads = HandFeelsReads;
    // HandDevices: sending a force and feeding the watchdog are writes (hand_devices.hpp).
    using writes = sched::Components<HandDevices, components::HandForce, components::SentForceLog, HandLinks>;
    void operator()(sched::SystemContext& ctx);
};

struct ForceCheckSystem {
    static constexpr std::string_view name = "force_check";
    static constexpr std::string_view lane = "sim";
    static constexpr std::string_view phase = "output";
    static constexpr std::string_view rate = "position_check";
    using reads = HandFeelsReads;
    using writes = sched::Components<components::ForceChecks>;
    void operator()(sched::SystemContext& ctx);
};

struct ForceEstimateSystem {
    static constexpr std::string_view name = "force_estimate";
    static constexpr std::string_view lane = "sim";
    static constexpr std::string_view phase = "output";
    static constexpr std::string_view rate = "position_estimate";
    using reads = sched::Components<components::ForceChecks, components::HandInput>;
    using writes = sched::Components<components::HandForce>;
    void operator()(sched::SystemContext& ctx);
};

// Sends each hand's current force to its device every tick (the paper scheme's "reused ten times").
struct ForceOutputSystem {
    static constexpr std::string_view name = "force_output";
    static constexpr std::string_view lane = "sim";
    static constexpr std::string_view phase = "output";
    static constexpr std::string_view rate = "haptic";
    using reads = sched::Components<components::HandCube, components::HandInput>;
    // HandForce: a hand whose device is gone is set to feel nothing. HandDevices: sending is a write.
    using writes = sched::Components<HandDevices, components::HandForce, components::SentForceLog, HandLinks>;
    void operator()(sched::SystemContext& ctx);
};

} // namespace ikebana::systems
