#include <gtest/gtest.h>

#include <atomic>
#include <thread>

#include "engine/devices/mouse_keyboard_device.hpp"

using namespace ikebana;
using namespace ikebana::devices;

namespace {
struct FakePointer : platform::PointerSource {
    platform::PointerState state = [] {
        platform::PointerState s;
        s.cursor_px = {400, 300};
        s.window_px = {800, 600};
        return s;
    }();
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

namespace {
// A ray from an eye through a point (device space), as the window aims the cursor.
platform::PointerRay ray_to(glm::dvec3 eye, glm::dvec3 through, int which_eye = -1) {
    platform::PointerRay r;
    r.origin_m = eye;
    r.direction = glm::normalize(through - eye);
    r.eye = which_eye;
    r.valid = true;
    return r;
}
// Distance of a point from a ray.
double off_ray(const platform::PointerRay& r, glm::dvec3 p) { return glm::length(glm::cross(p - r.origin_m, r.direction)); }

// The right hand with the cursor aimed at it from an eye, read once.
struct AimedRightHand {
    FakePointer pointer;
    MouseKeyboardHands hands{pointer};
    std::unique_ptr<HapticDevice> right = hands.hand(1);
    glm::dvec3 eye, start;
    explicit AimedRightHand(glm::dvec3 eye_m) : eye(eye_m), start(right->poll(0)->position) {
        pointer.state.ray = pointer.state.ray_before = ray_to(eye, start);
        EXPECT_TRUE(right->poll(1000).ok());
    }
    // The cursor moved by px onto where `through` is seen.
    void move(glm::dvec2 px, glm::dvec3 through) {
        pointer.state.cursor_px += px;
        pointer.state.ray_before = pointer.state.ray;
        pointer.state.ray = ray_to(eye, through);
    }
};
} // namespace

TEST(MouseKeyboard, AnAimedCursorTakesTheHandWhereThePointUnderItGoesAtTheHandsDepth) {
    AimedRightHand a({0.03, -0.6, 0.35});
    auto& right = a.right;
    auto& pointer = a.pointer;
    EXPECT_EQ(right->poll(1000)->position, a.start) << "a cursor on the hand moves nothing";
    // The cursor goes to where a point 4 cm right and 3 cm up of the hand, at its depth, is seen.
    const glm::dvec3 goal = a.start + glm::dvec3{0.04, 0.0, 0.03};
    a.move({20.0, -15.0}, goal);
    EXPECT_LT(glm::length(right->poll(2000)->position - goal), 1e-9) << "under the cursor, at its depth";
    // Read again (the window reads once a frame, the hands every tick): no further.
    EXPECT_LT(glm::length(right->poll(3000)->position - goal), 1e-9);
    // The wheel: along the ray, 1 cm deeper a click, still under the cursor.
    pointer.state.scroll += 2.0;
    const glm::dvec3 deeper = right->poll(4000)->position;
    EXPECT_NEAR(deeper.y - goal.y, 0.02, 1e-9);
    EXPECT_LT(off_ray(pointer.state.ray, deeper), 1e-9);
    EXPECT_LT(deeper.z, goal.z) << "along a ray that falls away from an eye above the hand";
}

TEST(MouseKeyboard, AnAimedShiftDragTakesTheHandAwayAsFarAsTheCursorWentUpAtItsDepth) {
    AimedRightHand a({0.0, -0.6, 0.35});
    a.pointer.state.depth_modifier = true;
    a.move({0.0, -30.0}, a.start + glm::dvec3{0.0, 0.0, 0.05});
    const glm::dvec3 after = a.right->poll(2000)->position;
    EXPECT_NEAR(after.y - a.start.y, 0.05, 1e-9) << "5 cm up at its depth: 5 cm away";
    EXPECT_NEAR(after.z, a.start.z, 1e-12);
}

TEST(MouseKeyboard, AnAimedCursorThatCrossesIntoTheOtherEyesImageMovesNoHand) {
    AimedRightHand a({-0.03, -0.6, 0.35});
    a.eye = {0.03, -0.6, 0.35};
    a.move({300.0, 0.0}, a.start + glm::dvec3{-0.25, 0.0, 0.0});
    a.pointer.state.ray.eye = 1; // the right eye's image; the cursor was in the left's
    EXPECT_EQ(a.right->poll(2000)->position, a.start) << "the window puts the cursor back on the hand instead";
    // A camera that turned under a still cursor: the window aims both rays through the new camera.
    a.pointer.state.ray_before = a.pointer.state.ray = ray_to({0.2, -0.5, 0.35}, a.start + glm::dvec3{0.1, 0.0, 0.0}, 1);
    a.pointer.state.cursor_px.x += 1.0;
    EXPECT_EQ(a.right->poll(3000)->position, a.start);
}
