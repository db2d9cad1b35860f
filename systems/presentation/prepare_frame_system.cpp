#include "systems/presentation/prepare_frame_system.hpp"

#include "engine/ecs/registry.hpp"
#include "systems/presentation/draw_list.hpp"
#include "systems/presentation/hud.hpp"

namespace ikebana::systems {

void PrepareFrameSystem::operator()(sched::SystemContext& ctx) {
    auto& r = ctx.registry;
    const auto* received = r.resource<const ReceivedFrames>();
    auto* prepared = r.resource<components::PreparedFrame>();
    if (!received || !prepared) return;
    const auto& frame = received->latest();
    prepared->list = build_draw_list(frame);
    const auto* scenery = r.resource<const components::Scenery>();
    if (scenery) prepared->list.append(scenery->list);
    const auto* hud = r.resource<const components::HudInfo>();
    // The scenery's labels first: the HUD's panel is drawn over them.
    prepared->overlay = scenery ? scenery->labels : std::vector<render::OverlayPanel>{};
    for (auto& panel : hud_panels(frame, hud ? *hud : components::HudInfo{})) prepared->overlay.push_back(std::move(panel));
    ++prepared->prepared;
}

} // namespace ikebana::systems
