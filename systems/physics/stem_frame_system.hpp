#pragma once
// Keeps every stem's material frame (components::StemFrame) with its stem, once a tick after the
// stem's points have moved and been kept out of the table: its directors carried with the segments,
// set where a hand or the kenzan holds them, and turned to the twist of least energy (stem_frame.hpp).
// The next tick's hinges read their rest bends' directions in it.
#include <string_view>
#include <vector>

#include "components/physics.hpp"
#include "components/stem.hpp"
#include "engine/sched/system.hpp"
#include "systems/physics/stem_frame.hpp"

namespace ikebana::systems {

struct StemFrameSystem {
    static constexpr std::string_view name = "stem_frame";
    static constexpr std::string_view lane = "sim";
    static constexpr std::string_view phase = "constraints";
    static constexpr std::string_view rate = "haptic";
    using reads = sched::Components<components::StemPoints, components::StemRestShape, components::StemSprings, components::BodyCapacity>;
    using writes = sched::Components<components::StemFrame>;

    void operator()(sched::SystemContext& ctx);

private:
    physics::FrameScratch scratch_; // kept from tick to tick, sized for the scene's longest stem: the 1 kHz loop does not allocate
    const components::BodyCapacity* sized_for_ = nullptr;
};

} // namespace ikebana::systems
