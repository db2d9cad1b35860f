#pragma once
// The world as the renderer's draw list, from the published snapshot (never the simulation's
// registry): the table, the kenzan's base and its pins (one instanced cylinder), each stem from its
// mass points (a cylinder per segment), petals, leaves and heads placed on their stem points, and the
// two hand cubes.
#include "components/snapshot.hpp"
#include "engine/render/draw_list.hpp"

namespace ikebana::systems {

[[nodiscard]] render::DrawList build_draw_list(const components::FrameSnapshot& frame);

} // namespace ikebana::systems
