#include "systems/haptics/grab_system.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "engine/devices/device_angles.hpp"
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

glm::dquat device_turn(glm::dvec3 rotation_rad, double yaw_rad) {
    const glm::dquat device = devices::turn_of_angles(rotation_rad);
    const glm::dquat camera = glm::angleAxis(yaw_rad, glm::dvec3{0, 0, 1});
    return camera * device * glm::conjugate(camera);
}

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
        [&](ecs::Entity hand, const HandCube& cube, const HandInput& input, const HandProxy& proxy, HandGrip& grip) {
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
                    // A hand takes a branch by its stem: a twig moves with it (one body), and what a held
                    // thing is (cut, inserted, scored) is the flower's.
                    if (r.all_of<StemFork>(flower)) return;
                    for (std::size_t i = 0; i < points.position_m.size(); ++i) {
                        if (!within_grab(points.position_m[i], proxy.position_m, cube.edge_m, rest.diameter_m)) continue;
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
                    if (const auto* history = r.try_get<const InsertionHistory>(grip.held)) grip.cuts_seen = history->cuts;
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
            // A cut laid the stem's points anew along it: the hand takes the point now nearest it, where it is.
            if (const auto* history = r.try_get<const InsertionHistory>(grip.held); history && history->cuts != grip.cuts_seen) {
                grip.cuts_seen = history->cuts;
                let_go_of_direction(r, grip);
                if (!held_by_another_hand(r, grip, grip.held_point)) points->pinned[grip.held_point] = 0;
                std::uint32_t nearest = 0;
                for (std::uint32_t i = 1; i < points->position_m.size(); ++i) {
                    if (glm::length(points->position_m[i] - proxy.position_m) < glm::length(points->position_m[nearest] - proxy.position_m)) nearest = i;
                }
                grip.held_point = nearest;
                grip.held_offset_m = points->position_m[nearest] - proxy.position_m;
            }
            if (alone && !grip.holds_direction && points->position_m.size() >= 2) {
                // The neighbour nearer the hand: the grip spans the stem inside the fist. Taken where it is
                // now, so that a second hand letting go leaves the stem in the direction the two gave it.
                const std::uint32_t last = static_cast<std::uint32_t>(points->position_m.size() - 1);
                const std::uint32_t below = grip.held_point > 0 ? grip.held_point - 1 : grip.held_point + 1;
                const std::uint32_t above = grip.held_point < last ? grip.held_point + 1 : grip.held_point - 1;
                const auto& x = points->position_m;
                grip.second_point = glm::length(x[below] - proxy.position_m) <= glm::length(x[above] - proxy.position_m) ? below : above;
                // Both offsets as they are now, unturned: from here the grip turns with the device.
                grip.held_offset_m = x[grip.held_point] - proxy.position_m;
                grip.second_offset_m = x[grip.second_point] - proxy.position_m;
                grip.holds_direction = true;
                const auto* map = r.try_get<const WorkspaceMapping>(hand);
                grip.turn_at_grip = device_turn(input.rotation_rad, map ? map->yaw_rad : 0.0);
                grip.turned = glm::dquat{1, 0, 0, 0};
                const auto* frame = r.try_get<const StemFrame>(grip.held);
                const std::uint32_t segment = std::min(grip.held_point, grip.second_point);
                grip.director_at_grip = frame && segment < frame->director.size() ? frame->director[segment] : glm::dvec3{0.0};
            }
            if (grip.holds_direction) {
                // Toward the device's turn since the grip, at most max_turn_rad_s.
                const auto* map = r.try_get<const WorkspaceMapping>(hand);
                const double yaw = map ? map->yaw_rad : 0.0;
                const glm::dquat wanted = device_turn(input.rotation_rad, yaw) * glm::conjugate(grip.turn_at_grip);
                const double dot = std::clamp(std::abs(glm::dot(grip.turned, wanted)), 0.0, 1.0);
                const double gap = 2.0 * std::acos(dot);
                const double step = max_turn_rad_s * ctx.dt_s;
                grip.turned = gap <= step || gap < 1e-12 ? wanted : glm::slerp(grip.turned, wanted, step / gap);
                pin(grip.held_point, grip.turned * grip.held_offset_m);
                if (grip.second_point < points->position_m.size()) pin(grip.second_point, grip.turned * grip.second_offset_m);
                // The bark turns with the fist (the frame's update reads and clears the hold each tick).
                const std::uint32_t segment = std::min(grip.held_point, grip.second_point);
                if (auto* frame = r.try_get<StemFrame>(grip.held); frame && segment < frame->held.size() && glm::dot(grip.director_at_grip, grip.director_at_grip) > 0.5) {
                    frame->held[segment] = 1;
                    frame->held_director[segment] = grip.turned * grip.director_at_grip;
                }
            } else {
                pin(grip.held_point, grip.held_offset_m);
                // Two hands on one stem: each fist holds the bark where it grips, where the frame carried
                // it (the wrists' roll bends the stem: bending_system). Held by points alone, a stem could
                // spin about its own axis between the hands under any twisting moment.
                if (!alone) {
                    const auto last = static_cast<std::uint32_t>(points->position_m.size() - 1);
                    const std::uint32_t segment = std::min(grip.held_point, last > 0 ? last - 1 : 0u);
                    if (auto* frame = r.try_get<StemFrame>(grip.held); frame && segment < frame->held.size() && segment < frame->director.size()) {
                        frame->held[segment] = 1;
                        frame->held_director[segment] = frame->director[segment];
                    }
                }
            }
        });
}

} // namespace ikebana::systems
