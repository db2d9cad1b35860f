#include "systems/presentation/hud.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>

namespace ikebana::systems {

using components::HudInfo;

std::string felt_words(const components::HandStatus& hand) {
    // A device outside the safety chain (the mouse) pushes nothing: there is nothing to feel to report.
    if (!hand.sent.pushes) return "";
    const double sent = glm::length(hand.sent.sent_n);
    const double asked = glm::length(hand.force_n);
    char text[160];
    // What the device was written last (the transport's writer), and what the chain queued after it
    // where the two differ: a writer behind (a stalled hub) shows here before anything else does.
    const double queued = glm::length(hand.sent.queued_n);
    const int n = std::abs(queued - sent) > std::max(0.05, 0.1 * queued) ? std::snprintf(text, sizeof text, "   feels %.2f N (%.2f N queued)", sent, queued)
                                                                        : std::snprintf(text, sizeof text, "   feels %.2f N", sent);
    std::string words(text, static_cast<std::size_t>(std::max(n, 0)));
    // Said only where the request is far from what the hand gets, or while it fades out.
    if (hand.sent.held != devices::ForceHeld::fading && asked - sent <= std::max(0.5, 0.2 * asked)) return words;
    using devices::ForceHeld;
    switch (hand.sent.held) {
    case ForceHeld::at_limit: std::snprintf(text, sizeof text, " (pushing back at its %.0f N limit; the contact asks %.1f N)", hand.sent.max_force_n, asked); break;
    case ForceHeld::waiting:
        std::snprintf(text, sizeof text, " (not pushing yet: it engages once the force asked is small; ease the handle back, it asks %.1f N)", asked);
        break;
    case ForceHeld::ramping: std::snprintf(text, sizeof text, " (ramping up towards %.1f N)", std::min(asked, hand.sent.max_force_n)); break;
    case ForceHeld::fading: std::snprintf(text, sizeof text, " (fading out)"); break;
    case ForceHeld::rate_limited:
    case ForceHeld::none: std::snprintf(text, sizeof text, " (catching up with the %.1f N asked)", asked); break;
    }
    return words + text;
}

std::vector<std::string> hud_lines(const components::FrameSnapshot& frame, const HudInfo& info) {
    std::vector<std::string> lines;
    char text[160];
    std::snprintf(text, sizeof text, "%s  %.1f s   %s", info.title.c_str(), static_cast<double>(frame.sim_time_us) * 1e-6, info.keys.c_str());
    lines.emplace_back(text);
    for (const auto& l : info.lesson) lines.push_back(l);
    // Flowers nobody has touched yet, lying on the table, make one line: a line each pushed the
    // lesson's form up behind the panel.
    const auto touched = [&](std::size_t i) {
        const auto& f = frame.flowers[i];
        const auto holds = [&](const components::HandStatus& h) { return h.present && h.held_flower == static_cast<std::int32_t>(i); };
        return f.in_kenzan || f.fallen || f.insertions > 0 || f.bottom_broken || holds(frame.hands[0]) || holds(frame.hands[1]);
    };
    std::vector<std::pair<std::string, int>> lying; // species, how many, in the frame's order
    for (std::size_t i = 0; i < frame.flowers.size(); ++i) {
        if (touched(i)) continue;
        auto it = std::find_if(lying.begin(), lying.end(), [&](const auto& l) { return l.first == frame.flowers[i].species; });
        if (it == lying.end()) lying.emplace_back(frame.flowers[i].species, 1);
        else ++it->second;
    }
    std::string untouched;
    for (const auto& [species, n] : lying) untouched += (untouched.empty() ? "" : ", ") + (n > 1 ? std::to_string(n) + " " : "") + species;
    if (!untouched.empty()) lines.push_back("on the table, not in the kenzan: " + untouched);
    for (std::size_t i = 0; i < frame.flowers.size(); ++i) {
        if (!touched(i)) continue;
        const auto& f = frame.flowers[i];
        std::string state;
        if (f.fallen) {
            // Never a holding margin without the reason: a fallen stem leans on more pins.
            if (f.fall_yield_gravity_nm > 0.0) {
                std::snprintf(text, sizeof text, "FELL: %s (the pins gave way holding %.1fx its weight's moment)", components::fall_words(f.fall_reason),
                              f.fall_yield_holding_nm / f.fall_yield_gravity_nm);
            } else {
                std::snprintf(text, sizeof text, "FELL: %s", components::fall_words(f.fall_reason));
            }
            state = text;
        } else if (f.in_kenzan && f.holding_moment_nm < f.gravity_moment_nm) {
            std::snprintf(text, sizeof text, "tipping: the pins hold %.1fx its weight's moment", f.holding_moment_nm / f.gravity_moment_nm);
            state = text;
        } else if (f.in_kenzan && f.gravity_moment_nm > 0.0) {
            std::snprintf(text, sizeof text, "stands, holding %.1fx its weight's moment", f.holding_moment_nm / f.gravity_moment_nm);
            state = text;
        } else if (f.in_kenzan) {
            state = "stands upright";
        } else {
            state = "not in the kenzan";
        }
        std::snprintf(text, sizeof text, "%-14s insertions %u%s   %s", f.species.c_str(), f.insertions, f.bottom_broken ? " (bottom split)" : "",
                      state.c_str());
        lines.emplace_back(text);
    }
    for (std::size_t h = 0; h < 2; ++h) {
        const auto& hand = frame.hands[h];
        if (!hand.present) continue;
        const std::string device = info.device[h].empty() || info.device[h] == "no device" ? "no device" : info.device[h];
        std::string state;
        if (!hand.connected && device != "no device") state = std::string(" (") + components::device_link_words(hand.link) + ")";
        // A press that took nothing says so (a first-time trainee otherwise presses again and again).
        const bool took_nothing = !hand.holding && hand.grab_button;
        std::snprintf(text, sizeof text, "%s hand: %s%s%s%s", h ? "right" : "left", device.c_str(), state.c_str(), felt_words(hand).c_str(),
                      hand.holding ? "   holding a stem" : took_nothing ? "   took nothing" : "");
        lines.emplace_back(text);
        if (took_nothing) lines.emplace_back("  nothing in reach: put the cube on a stem (yellow: what it takes)");
    }
    for (const auto& r : info.result) lines.push_back(r);
    return lines;
}

std::vector<render::OverlayPanel> hud_panels(const components::FrameSnapshot& frame, const HudInfo& info) {
    render::OverlayPanel panel;
    panel.lines = hud_lines(frame, info);
    panel.scale = 1.5f;
    return {panel};
}

} // namespace ikebana::systems
