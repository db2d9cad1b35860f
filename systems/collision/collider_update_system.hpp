#pragma once
// Moves each part's collider to where its flower's stem is now: a stem segment becomes the capsule
// between its two mass points, a petal or leaf the sphere at its attachment point. Inactive parts are
// skipped: nothing collides with them, so nothing needs their collider.
#include <string_view>

#include "components/collision.hpp"
#include "components/flower.hpp"
#include "components/stem.hpp"
#include "engine/sched/system.hpp"

namespace ikebana::systems {

struct ColliderUpdateSystem {
    static constexpr std::string_view name = "collider_update";
    static constexpr std::string_view lane = "sim";
    static constexpr std::string_view phase = "collision";
    static constexpr std::string_view rate = "position_check";
    using reads = sched::Components<components::Part, components::StemPoints, components::StemFrame, components::ActiveCollider, components::PassiveCollider,
                                    ecs::ChildOf>;
    using writes = sched::Components<components::Collider, components::ColliderPass>;

    void operator()(sched::SystemContext& ctx);
};

} // namespace ikebana::systems
