#pragma once
// What each hand feels, sent to its device: the coupling spring between the device and the cube it
// drives (pressing on the table or the kenzan), plus the stem's pull on the point the hand holds
// (its weight, its bending, and, when both hands hold one flower, the stretch of the part between:
// equal and opposite on the two hands). The device's own safety chain clamps, rate-limits and ramps.
#include <string_view>

#include "components/hand.hpp"
#include "components/physics.hpp"
#include "components/stem.hpp"
#include "engine/sched/system.hpp"
#include "systems/physics/stem_dynamics.hpp"

namespace ikebana::systems {

struct HandForceSystem {
    static constexpr std::string_view name = "hand_force";
    static constexpr std::string_view lane = "sim";
    static constexpr std::string_view phase = "output";
    static constexpr std::string_view rate = "haptic";
    using reads = sched::Components<components::StemPoints, components::StemRestShape, components::StemSprings,
                                    components::StemClamp, components::PhysicsSettings>;
    using writes = sched::Components<components::HandState>;

    void operator()(sched::SystemContext& ctx);

    std::vector<glm::dvec3> force_scratch;
};

} // namespace ikebana::systems
