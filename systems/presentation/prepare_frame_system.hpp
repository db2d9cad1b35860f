#pragma once
// Prepare (main lane): the received snapshot becomes this frame's draw list (the world, plus the
// scenery such as the sample arrangement) and the HUD's panels. The window, `ikebana render` and the
// no-display fallback all draw what this system prepared, so an offscreen image shows what the
// trainee sees.
#include <string_view>

#include "components/presentation.hpp"
#include "engine/sched/system.hpp"
#include "systems/presentation/frame_channel.hpp"

namespace ikebana::systems {

struct PrepareFrameSystem {
    static constexpr std::string_view name = "prepare_frame";
    static constexpr std::string_view lane = "main";
    static constexpr std::string_view phase = "prepare";
    static constexpr std::string_view rate = "render";
    using reads = sched::Components<ReceivedFrames, components::Scenery, components::HudInfo>;
    using writes = sched::Components<components::PreparedFrame>;

    void operator()(sched::SystemContext& ctx);
};

} // namespace ikebana::systems
