#include <gtest/gtest.h>

#include <atomic>
#include <thread>

#include "engine/devices/mouse_keyboard_device.hpp"

using namespace ikebana;
using namespace ikebana::devices;

namespace {
struct FakePointer : platform::PointerSource {
    platform::PointerState state{{400, 300}, {800, 600}, false, false, false, 0.0};
    platform::PointerState read() override { return state; }
};
} // namespace

TEST(MouseKeyboard, MouseMovesTheActiveHandOnly) {
    FakePointer pointer;
    MouseKeyboardHands hands(pointer);
    auto left = hands.hand(0);
    auto right = hands.hand(1);
    const auto left0 = left->poll(0)->position;
    const auto right0 = right->poll(0)->position;
    pointer.state.cursor_px.x += 400; // half the window: half the 0.30 m workspace
    pointer.state.cursor_px.y -= 120; // up a fifth of the window: a fifth of 0.25 m
    EXPECT_NEAR(right->poll(1000)->position.x - right0.x, 0.15 - 0.06, 1e-12) << "clamped at the workspace edge";
    EXPECT_NEAR(right->poll(1000)->position.z - right0.z, 0.05, 1e-12);
    EXPECT_EQ(left->poll(1000)->position, left0);
}

TEST(MouseKeyboard, ShiftOrWheelMovesInDepth) {
    FakePointer pointer;
    MouseKeyboardHands hands(pointer);
    auto right = hands.hand(1);
    const auto start = right->poll(0)->position;
    pointer.state.depth_modifier = true;
    pointer.state.cursor_px.y -= 60;
    const auto after = right->poll(1000)->position;
    EXPECT_NEAR(after.y - start.y, 0.025, 1e-12);
    EXPECT_NEAR(after.z, start.z, 1e-12);
    pointer.state.depth_modifier = false;
    pointer.state.scroll += 3;
    EXPECT_NEAR(right->poll(2000)->position.y - after.y, 0.03, 1e-12);
}

TEST(MouseKeyboard, TabSwitchesHandsAndEachKeepsItsGrip) {
    FakePointer pointer;
    MouseKeyboardHands hands(pointer);
    auto left = hands.hand(0);
    auto right = hands.hand(1);
    pointer.state.grab_button = true;
    EXPECT_EQ(right->poll(0)->buttons, 1u) << "the right hand grabs";
    pointer.state.switch_hand = true;
    (void)right->poll(1000);
    EXPECT_EQ(hands.active_hand(), 0);
    pointer.state.switch_hand = false;
    pointer.state.grab_button = false;
    pointer.state.cursor_px.x -= 80;
    EXPECT_EQ(left->poll(2000)->buttons, 0u);
    EXPECT_EQ(right->poll(2000)->buttons, 1u) << "the right hand still holds what it grabbed";
    EXPECT_LT(left->poll(2000)->position.x, -0.06) << "the mouse now drives the left hand";
    EXPECT_FALSE(right->capabilities().has_force_output);
}

TEST(MouseKeyboard, RightDragTurnsTheViewAndLeavesTheHandsStill) {
    FakePointer pointer;
    MouseKeyboardHands hands(pointer);
    auto right = hands.hand(1);
    const auto start = right->poll(0)->position;
    pointer.state.orbit_button = true;
    pointer.state.cursor_px += glm::dvec2{200, -100};
    EXPECT_EQ(right->poll(1000)->position, start) << "the drag is the camera's";
    pointer.state.orbit_button = false;
    pointer.state.cursor_px.x += 80; // a tenth of the window: 3 cm, counted from where the drag ended
    EXPECT_NEAR(right->poll(2000)->position.x - start.x, 0.03, 1e-12);
}

// The pointer the app hands from its main thread to the simulation's thread gives back what was stored.
TEST(SharedPointer, ReadsWhatTheMainThreadStored) {
    platform::SharedPointerSource shared;
    EXPECT_FALSE(shared.read().grab_button);
    platform::PointerState s;
    s.cursor_px = {12, 34};
    s.grab_button = true;
    s.arrows = {1, -1};
    shared.store(s);
    const auto got = shared.read();
    EXPECT_EQ(got.cursor_px, s.cursor_px);
    EXPECT_TRUE(got.grab_button);
    EXPECT_EQ(got.arrows, s.arrows);
}

// The main thread stores while the 1 kHz thread reads, without a lock: every state read is one the
// main thread stored whole (never half of two), and never an older one than read before.
TEST(SharedPointer, CrossesThreadsWithoutTearingOrGoingBack) {
    platform::SharedPointerSource shared;
    std::atomic<bool> done{false};
    std::thread main_thread([&] {
        for (int i = 1; i <= 20000; ++i) {
            platform::PointerState s;
            s.cursor_px = {i, i};
            s.scroll = i;
            shared.store(s);
        }
        done.store(true);
    });
    double newest = 0.0;
    while (!done.load()) {
        const auto s = shared.read();
        ASSERT_EQ(s.cursor_px.x, s.cursor_px.y);
        ASSERT_EQ(s.cursor_px.x, s.scroll);
        ASSERT_GE(s.scroll, newest);
        newest = s.scroll;
    }
    main_thread.join();
    EXPECT_EQ(shared.read().scroll, 20000.0);
}

TEST(MouseKeyboard, ACursorPutBackInTheMiddleMovesTheHandOnceByWhatItMovedBefore) {
    FakePointer pointer;
    MouseKeyboardHands hands(pointer);
    auto right = hands.hand(1);
    const auto start = right->poll(0)->position;
    // The cursor reached x = 10 (390 px left) and the window put it back at 400.
    pointer.state.warped_from_px = {10.0, 300.0};
    pointer.state.cursor_px = {400.0, 300.0};
    const double moved = right->poll(1000)->position.x - start.x;
    EXPECT_NEAR(moved, -390.0 / 800.0 * 0.30, 1e-12);
    // The hands read the same frame again and again: a warp counts once.
    for (std::int64_t t = 2000; t < 40'000; t += 1000) EXPECT_NEAR(right->poll(t)->position.x - start.x, moved, 1e-12);
    // Then it goes on from the middle.
    pointer.state.warped_from_px = {-1.0, -1.0};
    pointer.state.cursor_px.x -= 100.0;
    EXPECT_NEAR(right->poll(50'000)->position.x - start.x, moved - 100.0 / 800.0 * 0.30, 1e-12);
}

TEST(MouseKeyboard, CtrlDragTurnsTheHandInsteadOfMovingIt) {
    FakePointer pointer;
    MouseKeyboardHands hands(pointer);
    auto right = hands.hand(1);
    const auto start = right->poll(0)->position;
    pointer.state.tilt_modifier = true;
    pointer.state.cursor_px.x -= 400.0; // half the window: a quarter turn
    pointer.state.cursor_px.y -= 300.0; // half its height up: a quarter turn about x, the other way
    const auto s = *right->poll(1000);
    EXPECT_EQ(s.position, start) << "the hand stays";
    EXPECT_NEAR(s.rotation.y, -M_PI / 2, 1e-12);
    EXPECT_NEAR(s.rotation.x, M_PI / 2, 1e-12);
}
