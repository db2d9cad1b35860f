#pragma once
// Finds the pins inside each stem from geometry (pin_geometry.hpp), and keeps each flower's history:
// a new insertion begins when a stem that was clear of the pins enters them. At that moment the
// bottom may split (breakage, section 3.1): with the species' probability for this insertion count,
// drawn from the world's RandomStream so that runs are reproducible.
#include <string_view>

#include "components/insertion.hpp"
#include "components/kenzan.hpp"
#include "components/stem.hpp"
#include "engine/sched/system.hpp"

namespace ikebana::systems {

struct InsertionTrackingSystem {
    static constexpr std::string_view name = "insertion_tracking";
    static constexpr std::string_view lane = "sim";
    static constexpr std::string_view phase = "insertion";
    static constexpr std::string_view rate = "haptic";
    using reads = sched::Components<components::StemPoints, components::StemRestShape, components::Kenzan,
                                    components::PinResistance, components::Grasp>;
    using writes = sched::Components<components::PinEngagement, components::InsertionHistory, components::RandomStream>;

    // A stem end that leaves the pins and is back within this time never really came out (the pull
    // of a grab unbending it, a tick of numerical jitter): the same insertion goes on. A trainee's
    // withdrawal and new push take far longer.
    std::int64_t min_time_out_us = 50'000;
    // Nor did an end that hovered over the tips: a stem lifted out in jerks (a mouse at 10 frames a
    // second) swings its end 3 mm above the tips and back 3 mm into them, which counted as a new
    // insertion or not depending on the last bit of a sum. Back after rising less than this, the end
    // makes a new entry only once it was out for `min_time_hovering_us`.
    double min_rise_out_m = 0.005;
    std::int64_t min_time_hovering_us = 500'000;
    // Or one back in the pins this far (sideways) from where it left them: a new place, a new entry.
    double min_move_out_m = 0.008;
    // An insertion counts once the pins are this deep in the stem, past their cone tips (1.5 mm): a
    // stem pushed down onto the tips in a jerk bounces off them before it goes in (a mouse moving
    // 1.25 cm a frame at 10 frames a second once counted two insertions for one push).
    double pierced_depth_m = 0.002;

    void operator()(sched::SystemContext& ctx);
};

} // namespace ikebana::systems
