#pragma once
// What the trainee reads on the heads-up display: per flower its insertion count, how much margin the
// pins have over gravity (Eq. 7 as moments), and whether it stands or fell; each hand's device and the
// force it feels; the keys; and, once the trainee has finished, the result.
#include <array>
#include <string>
#include <vector>

#include "engine/render/text_overlay.hpp"

namespace ikebana::game {

class World;

struct HudInfo {
    double time_s = 0.0;
    std::array<std::string, 2> device{"", ""}; // what drives each hand
    std::vector<std::string> result;           // the training result's lines, when finished
};

std::vector<std::string> hud_lines(World& world, const HudInfo& info);
std::vector<render::OverlayPanel> hud_panels(World& world, const HudInfo& info);

} // namespace ikebana::game
