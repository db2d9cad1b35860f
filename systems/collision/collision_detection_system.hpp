#pragma once
// Finds the contacts of this pass (paper 2.2): Active x Active and Active x Passive pairs only;
// Passive x Passive and anything Inactive are never tested. Two broad phases:
//  - the kenzan's own grid: the pins under a collider are found by dividing by the pitch, O(1);
//  - a uniform spatial hash of the Active colliders (cells sorted once per pass), in which every
//    collider looks up the cells it covers, for parts and hands.
// Parts of one flower do not collide with each other (its springs keep them apart).
#include <cstdint>
#include <string_view>
#include <utility>
#include <vector>

#include "components/collision.hpp"
#include "components/flower.hpp"
#include "components/kenzan.hpp"
#include "engine/ecs/registry.hpp"
#include "engine/sched/system.hpp"

namespace ikebana::systems {

// The whole collision pass in one call. The world does not schedule it: it schedules
// SpreadCollisionSystem ("collision_detection"), which runs these same parts over the ticks after each
// collider update. Its own name says so, so that the two never share one in a schedule or a table.
struct CollisionDetectionSystem {
    static constexpr std::string_view name = "collision_pass";
    static constexpr std::string_view lane = "sim";
    static constexpr std::string_view phase = "collision";
    static constexpr std::string_view rate = "position_check";
    using reads = sched::Components<components::Collider, components::Kenzan, components::ActiveCollider,
                                    components::PassiveCollider, ecs::ChildOf>;
    using writes = sched::Components<components::Contacts, components::CollisionPass>;

    // A whole pass: begin, gather every pair, test them, the pins, publish.
    void operator()(sched::SystemContext& ctx);
};

// The pass in parts, for spreading it over ticks (spread_collision_system), on the world's
// CollisionPass (its working memory is kept between passes: no allocation in steady state).
namespace collision_pass {
// The world's pass state, made on first use (outside any view's iteration).
components::CollisionPass& of(ecs::Registry& r);
// Takes the colliders and indexes the Active ones.
void begin(ecs::Registry& r, components::CollisionPass& pass);
// Gathers the pairs of slice `slice` of `slices` of all colliders.
void gather(components::CollisionPass& pass, std::size_t slice, std::size_t slices);
// Tests the pairs of slice `slice` of `slices` (after every gather).
void query(components::CollisionPass& pass, std::size_t slice, std::size_t slices);
void query_pins(ecs::Registry& r, components::CollisionPass& pass);
// Makes what was found the Contacts.
void publish(ecs::Registry& r, components::CollisionPass& pass);
} // namespace collision_pass

} // namespace ikebana::systems
