#pragma once
// The main lane's presentation state (resources of the main registry): what the window, `ikebana
// render` and the no-display fallback all prepare and draw the same way.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "engine/render/draw_list.hpp"
#include "engine/render/text_overlay.hpp"

namespace ikebana::components {

// What the HUD says beyond the snapshot: what drives each hand, and the result once the trainee is done.
struct HudInfo {
    // The heading's first words and the keys it lists (a replay has its own).
    std::string title = "IKEBANA";
    std::string keys = "Enter: finish   arrows/right-drag: look around   Tab: other hand   Esc: quit";
    std::array<std::string, 2> device{"", ""};
    std::vector<std::string> result;
    std::vector<std::string> lesson; // the lesson's keys and what the held stem is doing against its role
};
// The heads-up text is what the app showing the world says (a replay's heading, its devices): a world
// put back to a saved moment (ecs::Registry::restore) keeps it.
inline void restore_resource(HudInfo&, HudInfo&&) noexcept {}

// Drawn every frame beside the world, fixed for the session: the scene's sample arrangement.
struct Scenery {
    render::DrawList list;
    std::vector<render::OverlayPanel> labels; // names on it, anchored to the world (text_overlay.hpp)
};

// This frame, ready for the renderer: the world's draw list with the scenery, and the HUD's panels.
struct PreparedFrame {
    render::DrawList list;
    std::vector<render::OverlayPanel> overlay;
    std::uint64_t prepared = 0; // frames prepared so far
};

} // namespace ikebana::components
