#pragma once
// Both-hand bending as the trainee does it (paper 2.4, Figures 6-8): both hands hold one stem with
// their device tips together; the index fingers are the supports A and B (L apart, centred where the
// hands are), the thumbs push the middle. Rolling the two devices against each other opens the bend:
// theta = pi - |roll_left - roll_right|, counted from their rolls when they came together. The stem points between A and B take Eq. 4's shape, F^b
// (Eq. 5) is fed back to both hands against the push, and a bend beyond the species' threshold leaves
// a permanent set in the rest shape (the branch stays bent after release).
#include <string_view>

#include "components/hand.hpp"
#include "components/stem.hpp"
#include "engine/sched/system.hpp"

namespace ikebana::systems {

struct BendingSystem {
    static constexpr std::string_view name = "bending";
    static constexpr std::string_view lane = "sim";
    static constexpr std::string_view phase = "input";
    static constexpr std::string_view rate = "haptic";
    using reads = sched::Components<components::HandCube, components::HandInput, components::HandProxy, components::HandGrip,
                                    components::StemSprings, components::StemFrame>;
    using writes = sched::Components<components::Bending, components::StemPoints, components::StemRestShape>;

    void operator()(sched::SystemContext& ctx);

    double tips_together_m = 0.05; // closer than this, the two hands act as one bending grip
    double span_m = 0.08;          // L: a hand's width between the index fingers
    double max_bend_rad_s = 3.0;   // a bend follows the wrists at most this fast (a wrist's roll, about 170 degrees a second)
};

} // namespace ikebana::systems
