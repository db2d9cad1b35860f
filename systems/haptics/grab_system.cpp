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
        auto pin = [&](std::uint32_t i, glm::dvec3 offset) {
            auto& x = points->position_m[i];
            const glm::dvec3 target = hand.proxy_m + offset;
            points->velocity_m_s[i] = ctx.dt_s > 0.0 ? (target - x) / ctx.dt_s : glm::dvec3{0.0};
            x = target;
            points->pinned[i] = 1;
        };
        const auto* grasp = r.try_get<Grasp>(hand.held);
        const bool alone = !grasp || grasp->hands <= 1;
        if (!alone) let_go_of_direction(r, hand);
        if (alone && !hand.holds_direction && points->position_m.size() >= 2) {
            // The neighbour nearer the hand: the grip spans the stem inside the fist. Taken where it is
            // now, so that a second hand letting go leaves the stem in the direction the two gave it.
            const std::uint32_t last = static_cast<std::uint32_t>(points->position_m.size() - 1);
            const std::uint32_t below = hand.held_point > 0 ? hand.held_point - 1 : hand.held_point + 1;
            const std::uint32_t above = hand.held_point < last ? hand.held_point + 1 : hand.held_point - 1;
            const auto& x = points->position_m;
            hand.second_point = glm::length(x[below] - hand.proxy_m) <= glm::length(x[above] - hand.proxy_m) ? below : above;
            hand.second_offset_m = x[hand.second_point] - hand.proxy_m;
            hand.holds_direction = true;
        }
        pin(hand.held_point, hand.held_offset_m);
        if (hand.holds_direction && hand.second_point < points->position_m.size()) pin(hand.second_point, hand.second_offset_m);
    });
}

} // namespace ikebana::systems
