#pragma once
// Integrates every spring stem one tick (Eq. 1-3) at the haptic rate, so the stem the trainee feels is
// the stem that is simulated. External forces written by other systems this tick are consumed.
#include <cstdint>
#include <string_view>

#include "components/physics.hpp"
#include "components/stem.hpp"
#include "engine/sched/system.hpp"
#include "systems/physics/stem_dynamics.hpp"

namespace ikebana::systems {

struct SpringPhysicsSystem {
    static constexpr std::string_view name = "spring_physics";
    static constexpr std::string_view lane = "sim";
    static constexpr std::string_view phase = "physics";
    static constexpr std::string_view rate = "haptic";
    using reads = sched::Components<components::StemRestShape, components::StemSprings, components::StemClamp,
                                    components::PhysicsSettings>;
    using writes = sched::Components<components::StemPoints, components::StemLoads>;

    void operator()(sched::SystemContext& ctx);

    physics::StemSolverScratch scratch;
    std::uint64_t failed_steps = 0; // steps refused for a non-finite result (should stay 0)
};

} // namespace ikebana::systems
