#pragma once
// The mouse's readings as the hands get them while the cursor goes over the side panel and back. Over
// the panel the cursor is the trainee's to click and scroll with: the hands keep their last reading
// (they neither move nor take what is under them), but Tab, the panel's lean buttons and what the
// window says of the held stem still reach them. A stem held when the cursor went over the panel, its
// button let go there (a lean button was clicked), stays held back in the scene until the next press
// there ends. And the wheel's notches over the panel scrolled the panel: they never reach the hands
// (counted on re-entry, twelve notches threw a hand 240 mm and tore a stem out of the pins).
#include "engine/platform/pointer_input.hpp"

namespace ikebana::game {

class PanelPointer {
public:
    // The first reading of a session: the hands start from it.
    void start(const platform::PointerState& in) {
        *this = PanelPointer{};
        last_ = in;
        wheel_seen_ = in.scroll;
    }
    // A reading with the cursor in the scene, changed into what the hands would read (the button held
    // for a stem held over the panel, the panel's wheel notches taken out). Then give() it.
    void in_scene(platform::PointerState& in);
    // A reading over the panel: what of it reaches the hands (last() then).
    void over_panel(const platform::PointerState& in);
    // The reading the hands get (after in_scene, perhaps changed further: a press's grip).
    void give(const platform::PointerState& in) { last_ = in; }
    [[nodiscard]] const platform::PointerState& last() const noexcept { return last_; }
    // The button went down with this reading (it was up in the last one the hands got).
    [[nodiscard]] bool pressed(const platform::PointerState& in) const noexcept { return in.grab_button && !last_.grab_button; }

private:
    platform::PointerState last_{};
    bool held_over_panel_ = false;
    double wheel_seen_ = 0.0;       // the window's wheel count at its last reading
    double wheel_over_panel_ = 0.0; // of which this many notches turned over the panel
};

} // namespace ikebana::game
