#pragma once
// A scripted hand that pushes a stem into the kenzan and pulls it out again: holds the stem straight
// along its axis and moves it vertically at a set speed, stopping at a height or when the pins resist
// more than the hand can push. Releasing hands the stem to the physics (and the kenzan grip).
#include <string_view>

#include "components/insertion.hpp"
#include "components/stem.hpp"
#include "engine/sched/system.hpp"

namespace ikebana::systems {

struct ScriptedInsertionSystem {
    static constexpr std::string_view name = "scripted_insertion";
    static constexpr std::string_view lane = "sim";
    static constexpr std::string_view phase = "input";
    static constexpr std::string_view rate = "haptic";
    using reads = sched::Components<components::PinEngagement, components::StemRestShape>;
    using writes = sched::Components<components::ScriptedInsertion, components::StemPoints, components::Grasp>;

    void operator()(sched::SystemContext& ctx);
};

} // namespace ikebana::systems
