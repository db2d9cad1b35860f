#pragma once
// Finds the contacts of this pass (paper 2.2): Active x Active and Active x Passive pairs only;
// Passive x Passive and anything Inactive are never tested. Two broad phases:
//  - the kenzan's own grid: the pins under a collider are found by dividing by the pitch, O(1);
//  - a uniform spatial hash (cells sorted once per pass, then binary-searched) for parts and hands.
// Parts of one flower do not collide with each other (its springs keep them apart).
#include <cstdint>
#include <string_view>
#include <utility>
#include <vector>

#include "components/collision.hpp"
#include "components/flower.hpp"
#include "components/kenzan.hpp"
#include "engine/sched/system.hpp"

namespace ikebana::systems {

struct CollisionDetectionSystem {
    static constexpr std::string_view name = "collision_detection";
    static constexpr std::string_view lane = "sim";
    static constexpr std::string_view phase = "collision";
    static constexpr std::string_view rate = "position_check";
    using reads = sched::Components<components::Collider, components::Kenzan, components::ActiveCollider,
                                    components::PassiveCollider, ecs::ChildOf>;
    using writes = sched::Components<components::Contacts>;

    void operator()(sched::SystemContext& ctx);

    double cell_size_m = 0.03;
    // Working memory kept between passes (no allocation in steady state).
    std::vector<std::pair<std::int64_t, std::uint32_t>> cells;
    std::vector<ecs::Entity> entities;
    std::vector<ecs::Entity> owners;
    std::vector<std::uint8_t> active;
};

} // namespace ikebana::systems
