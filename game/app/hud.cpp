#include "game/app/hud.hpp"

#include <cstdio>

#include "components/hand.hpp"
#include "components/insertion.hpp"
#include "game/world/world.hpp"

namespace ikebana::game {

std::vector<std::string> hud_lines(World& w, const HudInfo& info) {
    std::vector<std::string> lines;
    char text[160];
    std::snprintf(text, sizeof text, "IKEBANA  %.1f s   Enter: finish   arrows/right-drag: look around   Tab: other hand   Esc: quit", info.time_s);
    lines.emplace_back(text);
    for (const auto& f : w.flowers) {
        const auto* h = w.sim.try_get<components::InsertionHistory>(f.entity);
        const auto* e = w.sim.try_get<components::PinEngagement>(f.entity);
        const auto* grip = w.sim.try_get<components::KenzanGrip>(f.entity);
        if (!h || !e || !grip) continue;
        std::string state;
        if (grip->fallen) {
            state = "FELL";
        } else if (e->in_kenzan && e->gravity_moment_nm > 0.0) {
            std::snprintf(text, sizeof text, "stands, holding %.1fx its weight's moment", e->holding_moment_nm / e->gravity_moment_nm);
            state = text;
        } else if (e->in_kenzan) {
            state = "stands upright";
        } else {
            state = "not in the kenzan";
        }
        std::snprintf(text, sizeof text, "%-14s insertions %u%s   %s", f.species.c_str(), h->insertions_total, h->bottom_broken ? " (bottom split)" : "",
                      state.c_str());
        lines.emplace_back(text);
    }
    w.sim.view<components::HandState>().each([&](ecs::Entity, components::HandState& hand) {
        if (hand.hand > 1) return;
        std::snprintf(text, sizeof text, "%s hand: %s%s   feels %.2f N%s", hand.hand ? "right" : "left", info.device[hand.hand].c_str(),
                      hand.connected ? "" : " (disconnected)", glm::length(hand.force_n), !hand.held.is_null() ? "   holding a stem" : "");
        lines.emplace_back(text);
    });
    for (const auto& r : info.result) lines.push_back(r);
    return lines;
}

std::vector<render::OverlayPanel> hud_panels(World& w, const HudInfo& info) {
    render::OverlayPanel panel;
    panel.lines = hud_lines(w, info);
    panel.scale = 1.5f;
    return {panel};
}

} // namespace ikebana::game
