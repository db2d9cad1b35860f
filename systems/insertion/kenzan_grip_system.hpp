#pragma once
// Holds a released stem in the kenzan, or lets it fall (paper Figure 12). A stem whose bottom is in
// the pins and that no hand holds is gripped: its bottom point stays put and its first segment is held
// by the root hinge (StemClamp) whose moment is capped at the pins' holding moment. If gravity's
// moment is larger the hinge yields every tick, and the stem tips over about the kenzan through the
// spring physics, onto the table: it never vanishes or jumps.
#include <string_view>

#include "components/insertion.hpp"
#include "components/stem.hpp"
#include "engine/sched/system.hpp"

namespace ikebana::systems {

struct KenzanGripSystem {
    static constexpr std::string_view name = "kenzan_grip";
    static constexpr std::string_view lane = "sim";
    static constexpr std::string_view phase = "insertion";
    static constexpr std::string_view rate = "haptic";
    using reads = sched::Components<components::PinEngagement, components::StemPoints, components::StemSprings,
                                    components::Grasp>;
    using writes = sched::Components<components::KenzanGrip, components::StemClamp, components::StemFrame>;

    void operator()(sched::SystemContext& ctx);

    // A stem has fallen when its end in the pins turned this far from where it was released (the pins
    // gave way), ...
    double fall_angle_rad = 0.4363; // 25 degrees
    // ... when its line from bottom to top is this far from the vertical (it lies rather than stands:
    // a stem pushed in nearly flat has fallen from the start; the lessons' lowest stems lean 75° ± 10°) ...
    double lying_angle_rad = 1.4835; // 85 degrees
    // ... or when its top is no higher above its bottom than this fraction of its length (a stem bent
    // over by its head, hanging down: its line may still look tilted less than the lying angle).
    double dropped_fraction = 0.1;
};

} // namespace ikebana::systems
