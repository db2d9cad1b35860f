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
#include "engine/ecs/registry.hpp"
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

    // A whole pass: begin, query every Active collider, the pins, publish.
    void operator()(sched::SystemContext& ctx);

    // The pass in parts, for spreading it over ticks (spread_collision_system): index the colliders;
    // sort the index (in runs, merged); query the Active ones of slice `slice` of `slices`; the pins;
    // make what was found the Contacts.
    void begin(ecs::Registry& r);
    void sort_cells(std::size_t run, std::size_t runs); // then, when runs > 1, merge_cells(runs)
    void merge_cells(std::size_t runs);
    void query(std::size_t slice, std::size_t slices);
    void query_pins(ecs::Registry& r);
    void publish(ecs::Registry& r);

    double cell_size_m = 0.03;
    // Working memory kept between passes (no allocation in steady state).
    std::vector<std::pair<std::int64_t, std::uint32_t>> cells;
    std::vector<std::pair<std::int64_t, std::uint32_t>> merged;
    std::vector<ecs::Entity> entities;
    std::vector<components::Collider> colliders; // as they were at begin(): the pass is one instant's
    std::vector<ecs::Entity> owners;
    std::vector<std::uint8_t> active;
    std::size_t active_count = 0;
    std::vector<std::uint32_t> candidates;
    std::vector<components::Contact> found; // this pass's, until published
    std::uint64_t pairs_tested = 0;
};

} // namespace ikebana::systems
