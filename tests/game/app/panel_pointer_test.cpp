#include <gtest/gtest.h>

#include "game/app/panel_pointer.hpp"

using ikebana::game::PanelPointer;
using ikebana::platform::PointerState;

// A first-time trainee scrolled the panel twelve notches, came back into the scene, and the hand
// (moved in depth by the wheel) jumped 240 mm at once: the notches had been kept back, not dropped.
TEST(PanelPointer, WheelNotchesOverThePanelNeverReachTheHands) {
    PanelPointer hands;
    PointerState in;
    in.scroll = 3.0; // from before this session
    hands.start(in);
    in.scroll = 5.0; // two notches in the scene: the hand goes in depth
    hands.in_scene(in);
    hands.give(in);
    EXPECT_EQ(hands.last().scroll, 5.0);
    for (int notch = 0; notch < 12; ++notch) {
        in.scroll += 1.0;
        hands.over_panel(in);
        EXPECT_EQ(hands.last().scroll, 5.0) << "over the panel the hands keep their reading";
    }
    in.scroll += 1.0; // one more, back in the scene
    PointerState back = in;
    hands.in_scene(back);
    hands.give(back);
    EXPECT_EQ(hands.last().scroll, 6.0) << "only the notch turned in the scene reaches them";
    // And out and in again: still counted once.
    in.scroll -= 4.0;
    hands.over_panel(in);
    PointerState again = in;
    hands.in_scene(again);
    EXPECT_EQ(again.scroll, 6.0);
}

TEST(PanelPointer, AStemHeldWhenTheButtonWentUpOverThePanelStaysHeldUntilTheNextPressInTheScene) {
    PanelPointer hands;
    PointerState in;
    hands.start(in);
    in.grab_button = true;
    hands.in_scene(in);
    EXPECT_TRUE(hands.pressed(in));
    hands.give(in);
    in.grab_button = false; // let go over the panel (a lean button clicked)
    hands.over_panel(in);
    EXPECT_TRUE(hands.last().grab_button) << "over the panel the hand keeps its grip";
    PointerState back = in;
    hands.in_scene(back);
    EXPECT_TRUE(back.grab_button) << "back in the scene it still holds";
    EXPECT_FALSE(hands.pressed(back));
    hands.give(back);
    PointerState press = in;
    press.grab_button = true;
    hands.in_scene(press);
    hands.give(press);
    PointerState release = in;
    hands.in_scene(release);
    EXPECT_FALSE(release.grab_button) << "the next press's release lets go";
}

TEST(PanelPointer, OverThePanelTabAndTheLeanButtonsStillReachTheHands) {
    PanelPointer hands;
    PointerState in;
    hands.start(in);
    in.cursor_px = {900.0, 100.0};
    in.switch_hand = true;
    in.tilt_presses = {1.0, 0.0};
    hands.over_panel(in);
    EXPECT_TRUE(hands.last().switch_hand);
    EXPECT_EQ(hands.last().tilt_presses.x, 1.0);
    EXPECT_EQ(hands.last().cursor_px, glm::dvec2(0.0)) << "the cursor's motion over the panel does not";
}
