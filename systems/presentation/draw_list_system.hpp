#pragma once
// The world as the renderer's draw list, at the render rate: the table, the kenzan's base and its
// pins (one instanced cylinder), each stem from its live mass points (a cylinder per segment), petals,
// leaves and heads placed on their stem points, and the two hand cubes. Written as a resource; the
// frame publisher hands it to the main lane.
#include <string_view>

#include "components/appearance.hpp"
#include "components/flower.hpp"
#include "components/hand.hpp"
#include "components/kenzan.hpp"
#include "components/physics.hpp"
#include "components/stem.hpp"
#include "engine/render/draw_list.hpp"
#include "engine/sched/system.hpp"

namespace ikebana::systems {

struct DrawListSystem {
    static constexpr std::string_view name = "draw_list";
    static constexpr std::string_view lane = "sim";
    static constexpr std::string_view phase = "present";
    static constexpr std::string_view rate = "render";
    using reads = sched::Components<components::StemPoints, components::StemRestShape, components::Part, components::FlowerLook,
                                    components::Kenzan, components::Table, components::HandCube, components::HandProxy,
                                    components::HandInput, ecs::ChildOf>;
    using writes = sched::Components<render::DrawList>;

    void operator()(sched::SystemContext& ctx);
};

// The list itself (also for `ikebana render`, which draws on the deterministic clock).
render::DrawList build_draw_list(ecs::Registry& registry);

} // namespace ikebana::systems
