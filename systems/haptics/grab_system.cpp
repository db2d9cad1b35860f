#include "systems/haptics/grab_system.hpp"

#include <cmath>
#include <limits>

#include "engine/ecs/registry.hpp"

namespace ikebana::systems {

using namespace components;

namespace {
bool held_by_another_hand(ecs::Registry& r, const HandGrip& grip, std::uint32_t point) {
    bool other = false;
    r.view<const HandGrip>().each([&](ecs::Entity, const HandGrip& g) {
        if (&g == &grip || g.held != grip.held) return;
        other = other || g.held_point == point || (g.holds_direction && g.second_point == point);
    });
    return other;
}
} // namespace

void let_go_of_direction(ecs::Registry& r, HandGrip& grip) {
    if (!grip.holds_direction) return;
    grip.holds_direction = false;
    auto* points = r.try_get<StemPoints>(grip.held);
    if (points && grip.second_point < points->pinned.size() && grip.second_point != grip.held_point &&
        !held_by_another_hand(r, grip, grip.second_point))
        points->pinned[grip.second_point] = 0;
}

void release_hold(ecs::Registry& r, HandGrip& grip) {
    if (grip.held.is_null()) return;
    let_go_of_direction(r, grip);
    if (auto* points = r.try_get<StemPoints>(grip.held); points && grip.held_point < points->pinned.size()) {
        if (!held_by_another_hand(r, grip, grip.held_point)) points->pinned[grip.held_point] = 0;
    }
    if (auto* grasp = r.try_get<Grasp>(grip.held); grasp && grasp->hands > 0) --grasp->hands;
    grip.held = ecs::null_entity;
}

void GrabSystem::operator()(sched::SystemContext& ctx) {
    auto& r = ctx.registry;
    r.view<const HandCube, const HandInput, const HandProxy, HandGrip>().each(
        [&](ecs::Entity, const HandCube& cube, const HandInput& input, const HandProxy& proxy, HandGrip& grip) {
            const bool pressed = (input.buttons & 1u) != 0;
            const bool was_pressed = (input.previous_buttons & 1u) != 0;
            if (!input.connected || !pressed) {
                release_hold(r, grip); // a lost device lets go as an open hand does
                return;
            }
            if (!was_pressed && grip.held.is_null()) {
                // Unify with the nearest stem point inside the cube (its half edge plus the stem's radius).
                double best = std::numeric_limits<double>::infinity();
                r.view<const StemPoints, const StemRestShape>().each([&](ecs::Entity flower, const StemPoints& points, const StemRestShape& rest) {
                    const double reach = 0.5 * cube.edge_m + 0.5 * rest.diameter_m;
                    for (std::size_t i = 0; i < points.position_m.size(); ++i) {
                        const glm::dvec3 d = glm::abs(points.position_m[i] - proxy.position_m);
                        if (d.x > reach || d.y > reach || d.z > reach) continue;
                        const double dist = glm::length(points.position_m[i] - proxy.position_m);
                        if (dist < best) {
                            best = dist;
                            grip.held = flower;
                            grip.held_point = static_cast<std::uint32_t>(i);
                        }
                    }
                });
                if (!grip.held.is_null()) {
                    if (auto* grasp = r.try_get<Grasp>(grip.held)) ++grasp->hands;
                    // The point stays where it was in the hand: snapping it to the cube's centre would
                    // stretch the stem's stiff springs by millimetres in one tick (a knock in the hand).
                    grip.held_offset_m = r.get<const StemPoints>(grip.held).position_m[grip.held_point] - proxy.position_m;
                }
            }
            if (grip.held.is_null()) return;
            auto* points = r.try_get<StemPoints>(grip.held);
            if (!points || grip.held_point >= points->position_m.size()) {
                grip.held = ecs::null_entity; // the flower is gone
                return;
            }
            auto pin = [&](std::uint32_t i, glm::dvec3 offset) {
                auto& x = points->position_m[i];
                const glm::dvec3 target = proxy.position_m + offset;
                points->velocity_m_s[i] = ctx.dt_s > 0.0 ? (target - x) / ctx.dt_s : glm::dvec3{0.0};
                x = target;
                points->pinned[i] = 1;
            };
            const auto* grasp = r.try_get<const Grasp>(grip.held);
            const bool alone = !grasp || grasp->hands <= 1;
            if (!alone) let_go_of_direction(r, grip);
            if (alone && !grip.holds_direction && points->position_m.size() >= 2) {
                // The neighbour nearer the hand: the grip spans the stem inside the fist. Taken where it is
                // now, so that a second hand letting go leaves the stem in the direction the two gave it.
                const std::uint32_t last = static_cast<std::uint32_t>(points->position_m.size() - 1);
                const std::uint32_t below = grip.held_point > 0 ? grip.held_point - 1 : grip.held_point + 1;
                const std::uint32_t above = grip.held_point < last ? grip.held_point + 1 : grip.held_point - 1;
                const auto& x = points->position_m;
                grip.second_point = glm::length(x[below] - proxy.position_m) <= glm::length(x[above] - proxy.position_m) ? below : above;
                grip.second_offset_m = x[grip.second_point] - proxy.position_m;
                grip.holds_direction = true;
            }
            pin(grip.held_point, grip.held_offset_m);
            if (grip.holds_direction && grip.second_point < points->position_m.size()) pin(grip.second_point, grip.second_offset_m);
        });
}

} // namespace ikebana::systems
