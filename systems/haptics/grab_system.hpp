#pragma once
// Grabbing and both-hand unification (Figure 5): pressing the button with a stem inside the hand cube
// unifies the cube with the nearest stem mass point; that point then follows the hand. Two hands may
// hold two flowers, or two points of one flower: the part held by neither then stretches or shrinks
// through its springs. Releasing lets the point go (it falls, or stays if inserted in the kenzan).
#include <string_view>

#include "components/hand.hpp"
#include "components/insertion.hpp"
#include "components/stem.hpp"
#include "engine/sched/system.hpp"

namespace ikebana::systems {

struct GrabSystem {
    static constexpr std::string_view name = "grab";
    static constexpr std::string_view lane = "sim";
    static constexpr std::string_view phase = "input";
    static constexpr std::string_view rate = "haptic";
    using reads = sched::Components<components::HandCube, components::StemRestShape>;
    using writes = sched::Components<components::HandState, components::StemPoints, components::Grasp>;

    void operator()(sched::SystemContext& ctx);
};

} // namespace ikebana::systems
