#pragma once
// Keeps stem points above the table: a point that ends a step below the surface is put back on it,
// loses its velocity into the table, and slides with Coulomb friction. A position correction after the
// implicit step, so the stiff contact costs nothing in stability.
#include <string_view>

#include "components/physics.hpp"
#include "components/stem.hpp"
#include "engine/sched/system.hpp"

namespace ikebana::systems {

struct TableSupportSystem {
    static constexpr std::string_view name = "table_support";
    static constexpr std::string_view lane = "sim";
    static constexpr std::string_view phase = "constraints";
    static constexpr std::string_view rate = "haptic";
    using reads = sched::Components<components::Table, components::StemRestShape, components::PhysicsSettings>;
    using writes = sched::Components<components::StemPoints>;

    void operator()(sched::SystemContext& ctx);
};

} // namespace ikebana::systems
