#pragma once
// The collision pass spread over the haptic ticks after each collider update, so that no tick carries
// all of it (it was 62 us at once, on one tick in 62, the haptic tick's 99th percentile): on the
// update's own tick nothing, then the colliders taken and the Active ones indexed, then the pairs
// gathered in `gather_slices` slices of the colliders, tested in `slices` slices, then the pins and the
// hand-over of the contacts: complete 11 ms after the update, well within the 62.5 ms to the next
// (nothing steers by them: they are shown and counted).
// The pass works on the colliders as they were at its index (a hand's moves every tick are seen at the
// next pass), so its contacts are one instant's, as the whole pass's are.
#include <cstdint>
#include <string_view>

#include "components/collision.hpp"
#include "systems/collision/collision_detection_system.hpp"

namespace ikebana::systems {

struct SpreadCollisionSystem {
    static constexpr std::string_view name = "collision_detection";
    static constexpr std::string_view lane = "sim";
    static constexpr std::string_view phase = "collision";
    static constexpr std::string_view rate = "haptic";
    using reads = sched::Components<components::Collider, components::Kenzan, components::ActiveCollider,
                                    components::PassiveCollider, ecs::ChildOf, components::ColliderPass>;
    // CollisionPass: where the pass is and what it took and found so far (the world's, in the registry).
    using writes = sched::Components<components::Contacts, components::CollisionPass>;

    void operator()(sched::SystemContext& ctx);

    // Configuration only: every change from tick to tick is in the registry's CollisionPass.
    std::uint32_t gather_slices = 4; // of all colliders, one a tick
    std::uint32_t slices = 4;        // of the pairs, one a tick
};

} // namespace ikebana::systems
