#include "systems/haptics/grab_system.hpp"

#include <cmath>
#include <limits>

#include "components/collision.hpp"
#include "engine/ecs/registry.hpp"
#include "systems/haptics/hand_input_system.hpp"

namespace ikebana::systems {

using namespace components;

void GrabSystem::operator()(sched::SystemContext& ctx) {
    auto& r = ctx.registry;
    r.view<HandState, HandCube>().each([&](ecs::Entity, HandState& hand, HandCube& cube) {
        const bool pressed = (hand.buttons & 1u) != 0;
        const bool was_pressed = (hand.previous_buttons & 1u) != 0;
        if (!hand.connected) return;
        if (!pressed && !hand.held.is_null()) {
            release_hold(r, hand);
            return;
        }
        if (pressed && !was_pressed && hand.held.is_null()) {
            // Unify with the nearest stem point inside the cube (its half edge plus the stem's radius).
            double best = std::numeric_limits<double>::infinity();
            r.view<StemPoints, StemRestShape>().each([&](ecs::Entity flower, StemPoints& points, StemRestShape& rest) {
                const double reach = 0.5 * cube.edge_m + 0.5 * rest.diameter_m;
                for (std::size_t i = 0; i < points.position_m.size(); ++i) {
                    const glm::dvec3 d = glm::abs(points.position_m[i] - hand.proxy_m);
                    if (d.x > reach || d.y > reach || d.z > reach) continue;
                    const double dist = glm::length(points.position_m[i] - hand.proxy_m);
                    if (dist < best) {
                        best = dist;
                        hand.held = flower;
                        hand.held_point = static_cast<std::uint32_t>(i);
                    }
                }
            });
            if (!hand.held.is_null()) {
                if (auto* grasp = r.try_get<Grasp>(hand.held)) ++grasp->hands;
                // The point stays where it was in the hand: snapping it to the cube's centre would
                // stretch the stem's stiff springs by millimetres in one tick (a knock in the hand).
                hand.held_offset_m = r.get<StemPoints>(hand.held).position_m[hand.held_point] - hand.proxy_m;
            }
        }
        if (hand.held.is_null()) return;
        auto* points = r.try_get<StemPoints>(hand.held);
        if (!points || hand.held_point >= points->position_m.size()) {
            hand.held = ecs::null_entity; // the flower is gone
            return;
        }
        auto& x = points->position_m[hand.held_point];
        const glm::dvec3 target = hand.proxy_m + hand.held_offset_m;
        points->velocity_m_s[hand.held_point] = ctx.dt_s > 0.0 ? (target - x) / ctx.dt_s : glm::dvec3{0.0};
        x = target;
        points->pinned[hand.held_point] = 1;
    });
}

} // namespace ikebana::systems
