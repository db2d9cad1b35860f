#include "systems/insertion/scripted_insertion_system.hpp"

#include <cmath>

#include "engine/ecs/registry.hpp"

namespace ikebana::systems {

using namespace components;

namespace {
void hold_straight(StemPoints& points, const StemRestShape& rest, glm::dvec3 bottom, glm::dvec3 axis, glm::dvec3 velocity) {
    double along = 0.0;
    for (std::size_t i = 0; i < points.position_m.size(); ++i) {
        if (i > 0) along += rest.segment_length_m[i - 1];
        points.position_m[i] = bottom + along * axis;
        points.velocity_m_s[i] = velocity;
        points.pinned[i] = 1;
    }
}
} // namespace

void ScriptedInsertionSystem::operator()(sched::SystemContext& ctx) {
    auto& r = ctx.registry;
    r.view<ScriptedInsertion, StemPoints, const StemRestShape, const PinEngagement, Grasp>().each(
        [&](ecs::Entity, ScriptedInsertion& hand, StemPoints& points, const StemRestShape& rest, const PinEngagement& engagement,
            Grasp& grasp) {
            using Stage = ScriptedInsertion::Stage;
            const double radius = 0.5 * rest.diameter_m;
            switch (hand.stage) {
            case Stage::idle:
            case Stage::lifted: hold_straight(points, rest, hand.bottom_m, hand.axis, glm::dvec3{0.0}); break;
            case Stage::pushing: {
                const double lowest = hand.bottom_m.z - radius * std::sqrt(std::max(0.0, 1.0 - hand.axis.z * hand.axis.z));
                if (lowest <= hand.stop_z_m || engagement.resistance_n > hand.max_push_n) {
                    hand.stage = Stage::released;
                    for (auto& p : points.pinned) p = 0;
                    for (auto& v : points.velocity_m_s) v = glm::dvec3{0.0};
                    break;
                }
                hand.bottom_m.z -= std::min(hand.speed_m_s * ctx.dt_s, lowest - hand.stop_z_m);
                hold_straight(points, rest, hand.bottom_m, hand.axis, glm::dvec3{0.0, 0.0, -hand.speed_m_s});
                break;
            }
            case Stage::released: break;
            case Stage::withdrawing:
                // The pins resist withdrawal as they resist insertion: a hand that cannot pull harder
                // than that holds the stem where it is.
                if (engagement.resistance_n > hand.max_push_n) {
                    hold_straight(points, rest, hand.bottom_m, hand.axis, glm::dvec3{0.0});
                    break;
                }
                hand.bottom_m.z += hand.speed_m_s * ctx.dt_s;
                hold_straight(points, rest, hand.bottom_m, hand.axis, glm::dvec3{0.0, 0.0, hand.speed_m_s});
                if (hand.bottom_m.z >= hand.lift_to_z_m) hand.stage = Stage::lifted;
                break;
            }
            grasp.hands = hand.stage == Stage::released ? 0 : 1;
        });
}

} // namespace ikebana::systems
