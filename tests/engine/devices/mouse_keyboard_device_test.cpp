#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <utility>
#include <thread>

#include "engine/devices/device_angles.hpp"
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
    // Tab back with the button up: the right hand keeps its grip (it dropped the stem it held) until
    // the button next goes down and up.
    pointer.state.switch_hand = true;
    (void)right->poll(3000);
    pointer.state.switch_hand = false;
    EXPECT_EQ(hands.active_hand(), 1);
    EXPECT_EQ(right->poll(4000)->buttons, 1u) << "still holding";
    pointer.state.grab_button = true;
    EXPECT_EQ(right->poll(5000)->buttons, 1u);
    pointer.state.grab_button = false;
    EXPECT_EQ(right->poll(6000)->buttons, 0u) << "let go when the button comes up";
    // And Tab with the button down hands the left an open hand until the button comes up and goes down.
    pointer.state.grab_button = true;
    (void)right->poll(7000);
    pointer.state.switch_hand = true;
    (void)right->poll(8000);
    pointer.state.switch_hand = false;
    EXPECT_EQ(left->poll(9000)->buttons, 0u) << "the button held for the right takes nothing with the left";
    pointer.state.grab_button = false;
    (void)left->poll(10000);
    pointer.state.grab_button = true;
    EXPECT_EQ(left->poll(11000)->buttons, 1u) << "a press of its own";
}

// Started over (R) with a hand's grip kept after Tab, the new world's hand took whatever lay under its
// start: a restart opens both hands and forgets the last reading.
TEST(MouseKeyboard, ARestartOpensBothHandsAndForgetsTheLastReading) {
    FakePointer pointer;
    MouseKeyboardHands hands(pointer);
    auto right = hands.hand(1);
    pointer.state.grab_button = true;
    EXPECT_EQ(right->poll(0)->buttons, 1u);
    pointer.state.switch_hand = true;
    (void)right->poll(1000);
    pointer.state.switch_hand = false;
    pointer.state.grab_button = false;
    (void)right->poll(2000);
    pointer.state.switch_hand = true; // back to the right: it keeps its grip with the button up
    (void)right->poll(3000);
    pointer.state.switch_hand = false;
    ASSERT_EQ(right->poll(4000)->buttons, 1u);
    pointer.state.hand_moves = 3; // where the old session's window had moved it
    hands.restart();
    hands.place(1, {0.05, -0.1, 0.1});
    const auto first = *right->poll(5000);
    EXPECT_EQ(first.buttons, 0u) << "an open hand";
    EXPECT_EQ(first.position, glm::dvec3(0.05, -0.1, 0.1)) << "where it was placed, not where an old move put it";
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

namespace {
constexpr double deg = M_PI / 180.0;
// Where the device's turn takes a stem held upright: its top's direction (device space: x right, y
// away from the viewer, z up).
glm::dvec3 top_of(const DeviceSample& s) { return turn_of_angles(s.rotation) * glm::dvec3{0, 0, 1}; }
// The turn from one sample to the next, as an angle and an axis.
std::pair<double, glm::dvec3> turn_between(const DeviceSample& a, const DeviceSample& b) {
    const glm::dquat d = glm::normalize(turn_of_angles(b.rotation) * glm::conjugate(turn_of_angles(a.rotation)));
    const double angle = 2.0 * std::acos(std::clamp(std::abs(d.w), 0.0, 1.0));
    const glm::dvec3 axis = glm::length(glm::dvec3(d.x, d.y, d.z)) > 1e-12 ? glm::normalize(glm::dvec3(d.x, d.y, d.z)) * (d.w < 0 ? -1.0 : 1.0) : glm::dvec3{0.0};
    return {angle, axis};
}
} // namespace

TEST(MouseKeyboard, CtrlDragTurnsTheHandInsteadOfMovingIt) {
    FakePointer pointer;
    MouseKeyboardHands hands(pointer);
    auto right = hands.hand(1);
    const auto start = right->poll(0)->position;
    pointer.state.tilt_modifier = true;
    pointer.state.cursor_px.x -= 360.0; // a quarter degree a pixel: a quarter turn
    const auto s = *right->poll(1000);
    EXPECT_EQ(s.position, start) << "the hand stays";
    const glm::dvec3 top = top_of(s);
    EXPECT_NEAR(top.x, -1.0, 1e-9) << "dragged left, its top leans to the left";
}

TEST(MouseKeyboard, DraggingUpLeansTheTopAwayFromTheViewerAndDownTowardThem) {
    FakePointer pointer;
    MouseKeyboardHands hands(pointer);
    auto right = hands.hand(1);
    (void)right->poll(0);
    pointer.state.tilt_modifier = true;
    pointer.state.cursor_px.y -= 100.0;
    const glm::dvec3 away = top_of(*right->poll(1000));
    EXPECT_NEAR(std::acos(away.z), 25.0 * deg, 1e-9);
    EXPECT_GT(away.y, 0.4);
    EXPECT_NEAR(away.x, 0.0, 1e-12);
    pointer.state.cursor_px.y += 300.0;
    const glm::dvec3 toward = top_of(*right->poll(2000));
    EXPECT_NEAR(std::acos(toward.z), 50.0 * deg, 1e-9);
    EXPECT_LT(toward.y, -0.7);
}

TEST(MouseKeyboard, ADragTurnsTheSameDegreesAPixelWhicheverWayTheStemAlreadyLeans) {
    // The trainee saw the same 100 px drag give 5 degrees once and 80 another time (issue 37).
    FakePointer pointer;
    MouseKeyboardHands hands(pointer);
    auto right = hands.hand(1);
    pointer.state.tilt_modifier = true;
    DeviceSample before = *right->poll(0);
    std::int64_t t = 0;
    for (const glm::dvec2 lean : {glm::dvec2{0, -160}, glm::dvec2{200, 0}, glm::dvec2{-90, 310}, glm::dvec2{0, -400}}) {
        pointer.state.cursor_px += lean; // somewhere else first
        before = *right->poll(t += 1000);
        pointer.state.cursor_px.x += 100.0;
        const auto after = *right->poll(t += 1000);
        const auto [angle, axis] = turn_between(before, after);
        EXPECT_NEAR(angle, 25.0 * deg, 1e-9) << "after a lean of " << lean.x << ", " << lean.y << " px";
        EXPECT_NEAR(axis.y, 1.0, 1e-9) << "about the axis away from the viewer: its top goes right as seen";
    }
}

TEST(MouseKeyboard, CtrlArrowsLeanTheStemFiveDegreesAPress) {
    FakePointer pointer;
    MouseKeyboardHands hands(pointer);
    auto right = hands.hand(1);
    const auto start = *right->poll(0);
    pointer.state.tilt_presses = {3.0, 0.0}; // three Ctrl+Right
    const auto three = *right->poll(1000);
    EXPECT_NEAR(turn_between(start, three).first, 15.0 * deg, 1e-9);
    EXPECT_GT(top_of(three).x, 0.2);
    pointer.state.tilt_presses = {0.0, 0.0}; // and three Ctrl+Left: back
    EXPECT_NEAR(turn_between(start, *right->poll(2000)).first, 0.0, 1e-6);
}

// A first-time trainee's Ctrl+arrows lifted soe back out of the kenzan's pins: turned about the grip,
// the stem's bottom swung out. Where the window says the held stem is held fast, a lean turns it about
// there: the hand goes round that point by the same turn, and the point stays where it is.
TEST(MouseKeyboard, AStemHeldFastTurnsAboutWhereItIsHeldAndTheHandGoesRoundIt) {
    FakePointer pointer;
    MouseKeyboardHands hands(pointer);
    auto right = hands.hand(1);
    const auto start = *right->poll(0);
    const glm::dvec3 bottom = start.position - glm::dvec3{0.0, 0.0, 0.06}; // 60 mm below the grip
    pointer.state.turn_about = true;
    pointer.state.turn_about_m = bottom;
    pointer.state.tilt_presses = {3.0, 0.0}; // three Ctrl+Right: 15 degrees
    const auto leaned = *right->poll(1000);
    EXPECT_NEAR(turn_between(start, leaned).first, 15.0 * deg, 1e-9) << "the same turn as about the grip";
    EXPECT_NEAR(glm::length(leaned.position - bottom), 0.06, 1e-9) << "the hand went round the point";
    EXPECT_NEAR(leaned.position.x - bottom.x, 0.06 * std::sin(15.0 * deg), 1e-9) << "its top to the right, as the stem leans";
    // A Ctrl+drag too.
    pointer.state.tilt_modifier = true;
    pointer.state.cursor_px.x -= 40; // 10 degrees back to the left
    const auto dragged = *right->poll(2000);
    EXPECT_NEAR(glm::length(dragged.position - bottom), 0.06, 1e-9);
    EXPECT_NEAR(dragged.position.x - bottom.x, 0.06 * std::sin(5.0 * deg), 1e-9);
    // Held by nothing, it turns about the grip: the hand stays.
    pointer.state.tilt_modifier = false;
    pointer.state.turn_about = false;
    pointer.state.tilt_presses = {4.0, 0.0};
    EXPECT_NEAR(glm::length(right->poll(3000)->position - dragged.position), 0.0, 1e-12);
}

namespace {
// A direction's lean as the gauge reads it: its tilt from the vertical toward where it points (x right,
// y away from the viewer), in radians.
glm::dvec2 gauge_lean(glm::dvec3 d) {
    d = glm::normalize(d);
    const double across = std::hypot(d.x, d.y);
    return across > 1e-12 ? std::atan2(across, d.z) / across * glm::dvec2{d.x, d.y} : glm::dvec2{0.0};
}
glm::dvec3 from_lean(glm::dvec2 lean) {
    const double tilt = glm::length(lean);
    return tilt < 1e-12 ? glm::dvec3{0, 0, 1} : glm::dvec3{std::sin(tilt) / tilt * lean, std::cos(tilt)};
}
} // namespace

// A first-time trainee found that dragging toward the viewer barely leant a stem lying flat (about the
// screen's horizontal axis a stem pointing right only rolls), that a Ctrl+arrow gave 1 to 4 degrees
// on the gauge instead of 5, and that the same drag did different things as the stem leant further.
// Knowing which way the stem points, a lean moves its tip the way asked by the degrees asked, on the
// gauge, whichever way it points now.
TEST(MouseKeyboard, KnowingWhichWayTheStemPointsALeanMovesItsTipTheWayAskedByTheDegreesAsked) {
    const MouseKeyboardHands::Config config;
    const auto tip_after = [&](glm::dvec3 along, glm::dvec2 steps, glm::dvec2 moved_px = {0.0, 0.0}) {
        return MouseKeyboardHands::lean_turn(config, along, moved_px, 0.0, steps) * along;
    };
    // From several leans, an arrow step and a 40 px drag (10 degrees) each way.
    for (const glm::dvec2 lean_deg : {glm::dvec2{0, 0}, glm::dvec2{30, 0}, glm::dvec2{0, -45}, glm::dvec2{-50, 35}, glm::dvec2{90, 0}, glm::dvec2{0, -90}}) {
        const glm::dvec3 along = from_lean(lean_deg * deg);
        for (const glm::dvec2 step : {glm::dvec2{1, 0}, glm::dvec2{-1, 0}, glm::dvec2{0, 1}, glm::dvec2{0, -1}}) {
            const glm::dvec2 moved = gauge_lean(tip_after(along, step)) - lean_deg * deg;
            EXPECT_NEAR(glm::length(moved - step * 5.0 * deg), 0.0, 1e-9) << "from " << lean_deg.x << ", " << lean_deg.y << " a step " << step.x << ", " << step.y;
            const glm::dvec2 dragged = gauge_lean(tip_after(along, {0, 0}, glm::dvec2{step.x, -step.y} * 40.0)) - lean_deg * deg;
            EXPECT_NEAR(glm::length(dragged - step * 10.0 * deg), 0.0, 1e-9) << "dragged, from " << lean_deg.x << ", " << lean_deg.y;
        }
    }
    // Leaning right, a step right adds 5 degrees to its tilt; lying flat to the right, a step toward the
    // viewer swings its tip toward them (about the fixed axis it only rolled).
    const glm::dvec3 thirty_right = from_lean(glm::dvec2{30, 0} * deg);
    EXPECT_NEAR(std::acos(tip_after(thirty_right, {1.0, 0.0}).z), 35.0 * deg, 1e-9);
    const glm::dvec3 near = tip_after({1.0, 0.0, 0.0}, {0.0, -1.0});
    EXPECT_LT(near.y, -std::sin(3.0 * deg)) << "its tip toward the viewer (5 degrees of lean, at 90 degrees' tilt 3.2 of turn)";
    EXPECT_NEAR(near.z, 0.0, 3e-3) << "still lying about flat";
    // The lean turns the stem the shortest way: no spin about itself.
    const glm::dquat q = MouseKeyboardHands::lean_turn(config, thirty_right, {37.0, -12.0}, 0.0, {});
    EXPECT_NEAR(glm::dot(glm::axis(q), thirty_right), 0.0, 1e-9);
    // Upright, the same as about the fixed axes.
    const glm::dvec3 up{0.0, 0.0, 1.0};
    for (const glm::dvec2 steps : {glm::dvec2{1.0, 0.0}, glm::dvec2{0.0, -1.0}, glm::dvec2{-2.0, 1.0}}) {
        const glm::dvec3 fixed = MouseKeyboardHands::drag_turn(config, {0.0, 0.0}, 0.0, steps) * up;
        EXPECT_NEAR(glm::length(tip_after(up, steps) - fixed), 0.0, 3e-3) << steps.x << ", " << steps.y; // both at once: within 0.2 degree
    }
    // Through the hands' readings: the window says which way the held stem points; a Ctrl+drag and
    // Ctrl+arrows both lean it so.
    FakePointer pointer;
    MouseKeyboardHands hands(pointer);
    auto hand = hands.hand(1);
    (void)hand->poll(0);
    const glm::dvec3 right{1.0, 0.0, 0.0};
    pointer.state.lean_along = true;
    pointer.state.lean_along_dir = right;
    pointer.state.tilt_presses = {0.0, -2.0};
    const auto leaned = *hand->poll(1000);
    EXPECT_NEAR(glm::length(gauge_lean(turn_of_angles(leaned.rotation) * right) - glm::dvec2{90.0, -10.0} * deg), 0.0, 1e-9);
    pointer.state.lean_along_dir = turn_of_angles(leaned.rotation) * right;
    pointer.state.tilt_modifier = true;
    pointer.state.cursor_px.y -= 40.0; // and back, dragged up (away): 10 degrees
    const auto back = *hand->poll(2000);
    EXPECT_NEAR(glm::length(turn_of_angles(back.rotation) * right - right), 0.0, 1e-9);
}

// A drag split into the window's readings, the window telling the hands each time which way the stem
// now points, leans it as the same drag read at once: the lean goes straight across the gauge.
TEST(MouseKeyboard, ALeanDraggedOverManyReadingsEndsWhereOneReadingWouldPutIt) {
    const glm::dvec3 along = from_lean(glm::dvec2{-20, 40} * deg);
    const glm::dvec2 drag{150.0, 90.0};
    glm::dvec3 ends[2];
    for (int readings : {1, 7}) {
        FakePointer pointer;
        MouseKeyboardHands hands(pointer);
        auto hand = hands.hand(1);
        const auto start = *hand->poll(0);
        pointer.state.lean_along = true;
        pointer.state.tilt_modifier = true;
        std::int64_t t = 0;
        DeviceSample now = start;
        for (int r = 0; r < readings; ++r) {
            pointer.state.lean_along_dir = turn_of_angles(now.rotation) * glm::conjugate(turn_of_angles(start.rotation)) * along;
            pointer.state.cursor_px += drag / static_cast<double>(readings);
            now = *hand->poll(t += 1000);
        }
        ends[readings == 1 ? 0 : 1] = turn_of_angles(now.rotation) * glm::conjugate(turn_of_angles(start.rotation)) * along;
    }
    EXPECT_NEAR(glm::length(ends[0] - ends[1]), 0.0, 1e-9);
    EXPECT_NEAR(glm::length(gauge_lean(ends[0]) - (glm::dvec2{-20, 40} * deg + glm::dvec2{150.0, -90.0} * (0.25 * deg))), 0.0, 1e-9);
}

TEST(MouseKeyboard, TurningTheCameraLeavesTheHandsWhereTheyAreInTheRoomTurnedAsTheyWere) {
    // The trainee saw a held stem go from "49 deg left front" to "57 deg left back" as the camera turned.
    FakePointer pointer;
    MouseKeyboardHands hands(pointer);
    auto right = hands.hand(1);
    (void)right->poll(0);
    pointer.state.tilt_modifier = true;
    pointer.state.cursor_px += glm::dvec2{-120.0, -80.0};
    const auto before = *right->poll(1000);
    pointer.state.tilt_modifier = false;
    // The room from the device: turned by the camera's yaw about the vertical (hand_input_system).
    const auto room = [](const DeviceSample& s, double yaw) {
        const glm::dquat camera = glm::angleAxis(yaw, glm::dvec3{0, 0, 1});
        return std::pair{camera * s.position, camera * turn_of_angles(s.rotation) * glm::conjugate(camera)};
    };
    for (const double yaw : {0.3, -1.1, 2.5}) {
        pointer.state.view_yaw_rad = yaw;
        const auto after = *right->poll(static_cast<std::int64_t>(2000 + 1000 * yaw));
        const auto [was_at, was_turned] = room(before, 0.0);
        const auto [is_at, is_turned] = room(after, yaw);
        EXPECT_NEAR(glm::length(is_at - was_at), 0.0, 1e-12) << "yaw " << yaw;
        EXPECT_NEAR(std::abs(glm::dot(is_turned, was_turned)), 1.0, 1e-12) << "yaw " << yaw;
    }
}

TEST(MouseKeyboard, TheTiltGestureForATurnReachesItThroughTheHandsReadings) {
    // What a scripted mouse sends to turn a hand from one set of angles to another: a drag sideways, one
    // up or down, then wheel clicks, each read on its own, ends where the gesture says.
    const MouseKeyboardHands::Config config;
    for (const auto& [from, to] : {std::pair{glm::dvec3{0.0}, glm::dvec3{0.3, -0.5, 0.2}}, std::pair{glm::dvec3{0.4, 0.2, -1.0}, glm::dvec3{-0.2, 0.9, 0.5}}}) {
        FakePointer pointer;
        MouseKeyboardHands hands(pointer);
        auto right = hands.hand(1);
        (void)right->poll(0);
        pointer.state.tilt_presses = {0.0, 0.0};
        // To `from` first: the hand starts unturned.
        std::int64_t t = 0;
        const auto send = [&](const MouseKeyboardHands::TiltGesture& g) {
            pointer.state.tilt_modifier = true;
            pointer.state.cursor_px.x += g.right_px;
            (void)right->poll(t += 1000);
            pointer.state.cursor_px.y += g.down_px;
            (void)right->poll(t += 1000);
            pointer.state.scroll += g.clicks;
            (void)right->poll(t += 1000);
        };
        const auto first = MouseKeyboardHands::tilt_gesture(config, glm::dvec3{0.0}, from);
        send(first);
        const auto there = right->poll(t += 1000)->rotation;
        EXPECT_LT(glm::length(there - first.reached), 1e-9);
        const auto g = MouseKeyboardHands::tilt_gesture(config, there, to);
        send(g);
        const auto reached = *right->poll(t += 1000);
        EXPECT_LT(glm::length(reached.rotation - g.reached), 1e-9) << "the gesture says where it ends";
        DeviceSample target;
        target.rotation = to;
        // Within whole pixels and half a wheel click (5°, about the vertical) of the turn asked for.
        EXPECT_LT(turn_between(reached, target).first, 2.5 * deg + 0.3 * deg);
    }
}

// Holding a stem, a scripted mouse turns it by a Ctrl+Shift drag (a twist about its own axis) and then
// one Ctrl+drag (the window leaning it the way the drag goes): the stem ends pointing where the turn
// asked, and the hand turned as asked, within the pixels' rounding.
TEST(MouseKeyboard, TheTiltGestureForAHeldStemTwistsAndLeansItWhereTheTurnAsked) {
    const MouseKeyboardHands::Config config;
    const glm::dvec3 along_hand = glm::normalize(glm::dvec3{0.3, -0.2, 1.0}); // the stem in the hand, unturned
    for (const auto& [from, to] : {std::pair{glm::dvec3{0.0}, glm::dvec3{0.3, -0.5, 0.2}}, std::pair{glm::dvec3{0.4, 0.2, -1.0}, glm::dvec3{-0.2, 0.9, 0.5}},
                                   std::pair{glm::dvec3{1.2, 0.0, 0.0}, glm::dvec3{1.25, 0.05, 0.02}}, std::pair{glm::dvec3{0.0}, glm::dvec3{0.0, 0.0, 2.5}}}) {
        FakePointer pointer;
        MouseKeyboardHands hands(pointer);
        auto right = hands.hand(1);
        std::int64_t t = 0;
        // To `from` first, holding nothing.
        const auto first = MouseKeyboardHands::tilt_gesture(config, glm::dvec3{0.0}, from);
        pointer.state.tilt_modifier = true;
        pointer.state.cursor_px.x += first.right_px;
        (void)right->poll(t += 1000);
        pointer.state.cursor_px.y += first.down_px;
        (void)right->poll(t += 1000);
        pointer.state.scroll += first.clicks;
        const auto there = *right->poll(t += 1000);
        // Now holding: the window says which way the stem points at each reading.
        const auto pointing = [&](const DeviceSample& s) { return turn_of_angles(s.rotation) * along_hand; };
        const auto g = MouseKeyboardHands::tilt_gesture(config, there.rotation, to, pointing(there));
        ASSERT_TRUE(g.held);
        EXPECT_EQ(g.clicks, 0);
        pointer.state.lean_along = true;
        pointer.state.lean_along_dir = pointing(there);
        pointer.state.depth_modifier = true; // Ctrl+Shift: the twist
        pointer.state.cursor_px.x += g.twist_px;
        const auto twisted = *right->poll(t += 1000);
        EXPECT_NEAR(glm::length(pointing(twisted) - pointing(there)), 0.0, 1e-9) << "a twist leaves it pointing where it pointed";
        pointer.state.depth_modifier = false;
        (void)right->poll(t += 1000);
        pointer.state.lean_along_dir = pointing(twisted);
        pointer.state.cursor_px += glm::dvec2(g.right_px, g.down_px);
        const auto reached = *right->poll(t += 1000);
        EXPECT_LT(glm::length(reached.rotation - g.reached), 1e-9) << "the gesture says where it ends";
        DeviceSample target;
        target.rotation = to;
        const double tip_off = std::acos(std::min(1.0, glm::dot(pointing(reached), pointing(target))));
        EXPECT_LT(tip_off, 0.2 * deg) << "its tip where the turn puts it, within whole pixels";
        EXPECT_LT(turn_between(reached, target).first, 0.4 * deg) << "the whole turn, its twist too";
    }
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

TEST(MouseKeyboard, TheWindowPutsTheActiveHandWhereAPressIsToTakeAStem) {
    FakePointer pointer;
    MouseKeyboardHands hands(pointer);
    auto left = hands.hand(0);
    auto right = hands.hand(1);
    const auto left0 = left->poll(0)->position;
    pointer.state.hand_moves = 1;
    pointer.state.hand_to_m = {0.05, -0.02, 0.01};
    pointer.state.grab_button = true;
    const auto s = *right->poll(1000);
    EXPECT_EQ(s.position, pointer.state.hand_to_m) << "there with the press";
    EXPECT_EQ(s.buttons, 1u);
    EXPECT_EQ(left->poll(1000)->position, left0);
    pointer.state.hand_to_m = {0.1, 0.1, 0.1}; // the same count: no second move
    EXPECT_EQ(right->poll(2000)->position, s.position);
}
