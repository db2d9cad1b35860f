#pragma once
// What the trainee reads on the heads-up display: per flower its insertion count, how much margin the
// pins have over gravity (Eq. 7 as moments), and whether it stands or fell; each hand's device and the
// force it feels; the keys; and, once the trainee has finished, the result. Everything comes from the
// frame snapshot the simulation publishes, never from the simulation's registry (another thread).
#include <string>
#include <vector>

#include "components/presentation.hpp"
#include "components/snapshot.hpp"
#include "engine/render/text_overlay.hpp"

namespace ikebana::systems {

std::vector<std::string> hud_lines(const components::FrameSnapshot& frame, const components::HudInfo& info);
// What a hand feels, as the HUD says it: the force its device really got (after the safety chain),
// and where that is far from what the simulation asks, why ("pushing back at its 3 N limit"). Empty
// for a hand whose device pushes nothing (the mouse).
std::string felt_words(const components::HandStatus& hand);
std::vector<render::OverlayPanel> hud_panels(const components::FrameSnapshot& frame, const components::HudInfo& info);

} // namespace ikebana::systems
