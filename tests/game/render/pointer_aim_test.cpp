#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <vector>

#include "game/render/pointer_aim.hpp"

using namespace ikebana;
using namespace ikebana::game;

namespace {

// A 1200x675 side-by-side window with the default camera.
struct Window {
    PointerView view{render::StereoRig{}, render::StereoMode::side_by_side, 0.0};
    platform::PointerState in = [] {
        platform::PointerState s;
        s.window_px = {1200.0, 675.0};
        s.cursor_px = {300.0, 300.0};
        return s;
    }();
    std::array<std::optional<glm::dvec3>, 2> hands{glm::dvec3{-0.08, -0.05, 0.05}, glm::dvec3{0.06, 0.0, 0.08}};
    PointerAim aim;
    std::vector<glm::dvec2> put; // where the cursor was put
    platform::PointerState read() {
        platform::PointerState s = in;
        aim.aim(s, view, hands, [&](glm::dvec2 px) { put.push_back(px); });
        in.cursor_px = s.cursor_px; // the window's cursor is where it was put
        return s;
    }
    double off(const platform::PointerRay& ray, glm::dvec3 p) const { return glm::length(glm::cross(p - ray.origin_m, ray.direction)); }
};

} // namespace

TEST(PointerAim, TheCursorStartsOnTheHandItDrivesAndItsRayPassesThroughThatHand) {
    Window w;
    const auto s = w.read();
    ASSERT_EQ(w.put.size(), 1u);
    EXPECT_LT(w.put[0].x, 600.0) << "in the left eye's image, where the cursor was";
    ASSERT_TRUE(s.ray.valid);
    EXPECT_EQ(s.ray.eye, -1);
    EXPECT_LT(w.off(s.ray, *w.hands[1]), 1e-6) << "the right hand is under the cursor";
    EXPECT_LT(w.off(s.ray_before, *w.hands[1]), 1e-6) << "and the cursor put there moves no hand";
}

TEST(PointerAim, TabCtrlAndTheOtherEyeEachPutTheCursorBackOnTheHand) {
    Window w;
    (void)w.read();
    const auto on = [&](int hand) { return w.off(w.read().ray, *w.hands[static_cast<std::size_t>(hand)]); };
    // Plain motion: the cursor is the trainee's; nothing put.
    w.in.cursor_px += glm::dvec2{5.0, 0.0};
    (void)w.read();
    (void)w.read();
    (void)w.read();
    const std::size_t settled = w.put.size();
    w.in.cursor_px += glm::dvec2{12.0, -7.0};
    const auto moved = w.read();
    EXPECT_EQ(w.put.size(), settled) << "a moving cursor is left alone";
    EXPECT_GT(w.off(moved.ray, *w.hands[1]), 1e-3);
    // Tab: onto the left hand.
    w.in.switch_hand = true;
    EXPECT_LT(on(0), 1e-6);
    EXPECT_EQ(w.aim.active_hand(), 0);
    w.in.switch_hand = false;
    // A Ctrl+drag moves the cursor but not the hand; let go, the cursor is on the hand again.
    w.in.tilt_modifier = true;
    w.in.cursor_px += glm::dvec2{40.0, 10.0};
    EXPECT_GT(on(0), 1e-3);
    w.in.tilt_modifier = false;
    EXPECT_LT(on(0), 1e-6);
    // Into the right eye's image: onto the hand as that eye shows it.
    w.in.cursor_px = {900.0, 300.0};
    const auto crossed = w.read();
    EXPECT_EQ(crossed.ray.eye, 1);
    EXPECT_GT(crossed.cursor_px.x, 600.0);
    EXPECT_LT(w.off(crossed.ray, *w.hands[0]), 1e-6);
}

TEST(PointerAim, ACameraTurnedUnderAStillCursorMovesNoHandAndThenTheCursorGoesBackOnIt) {
    Window w;
    (void)w.read();
    w.in.orbit_button = true;
    w.view.rig = render::orbited(w.view.rig, 0.3, 0.1);
    w.view.yaw_rad = 0.3;
    const auto turning = w.read();
    EXPECT_EQ(turning.ray.origin_m, turning.ray_before.origin_m);
    EXPECT_EQ(turning.ray.direction, turning.ray_before.direction) << "both through the new camera: no motion";
    w.in.orbit_button = false;
    const auto after = w.read();
    // Device space is the world turned back by the camera's yaw.
    const double c = std::cos(-0.3), s = std::sin(-0.3);
    const glm::dvec3 h = *w.hands[1];
    EXPECT_LT(w.off(after.ray, {c * h.x - s * h.y, s * h.x + c * h.y, h.z}), 1e-6);
}

TEST(PointerAim, PixelsPerMetreAreLargerForANearerHand) {
    const PointerView view{render::StereoRig{}, render::StereoMode::side_by_side, 0.0};
    const auto near = px_per_m_at(view, {1200.0, 675.0}, -1, {0.0, -0.2, 0.1});
    const auto far = px_per_m_at(view, {1200.0, 675.0}, -1, {0.0, 0.2, 0.1});
    ASSERT_TRUE(near && far);
    EXPECT_GT(near->x, far->x * 1.2);
    EXPECT_GT(near->y, far->y);
    // Equal scaling: across and up about the same near the middle of the view.
    const auto middle = px_per_m_at(view, {1200.0, 675.0}, -1, render::StereoRig{}.target_m);
    ASSERT_TRUE(middle);
    EXPECT_NEAR(middle->x / middle->y, 1.0, 0.25);
}

TEST(PointerAim, ACursorRestingAwayFromAHandThatCouldNotFollowGoesBackOntoIt) {
    Window w;
    (void)w.read();
    const std::size_t before = w.put.size();
    // The cursor goes on 60 px down; the hand stops at the table (it stays where it was here).
    w.in.cursor_px += glm::dvec2{0.0, 60.0};
    (void)w.read();
    (void)w.read();
    EXPECT_EQ(w.put.size(), before) << "a moment's rest is the trainee's";
    (void)w.read();
    const auto s = w.read();
    EXPECT_GT(w.put.size(), before) << "resting away from it, the cursor goes back onto the hand";
    EXPECT_LT(w.off(s.ray, *w.hands[1]), 1e-6);
}

// Pick by ray (issue 59): the cursor on a stem lying on the table puts the open hand on that stem,
// under the cursor, whatever its depth was, in a camera turned round the table too; a wheel notch is
// kept until the cursor next moves; nothing happens while it holds a stem or with Ctrl or Shift.
TEST(PointerAim, TheCursorOnAStemPutsTheOpenHandOnItUnderTheCursorWhateverItsDepth) {
    for (const double yaw : {0.0, 0.6}) {
        components::FrameSnapshot frame{};
        components::FlowerStatus stem{};
        stem.diameter_m = 0.006;
        for (int i = 0; i <= 10; ++i) stem.points_m.push_back({-0.15 + 0.03 * i, 0.04, 0.005});
        frame.flowers.push_back(stem);
        frame.hands[1].present = true;
        PointerView view{render::StereoRig{}, render::StereoMode::mono, yaw};
        const glm::dvec2 window{1200.0, 675.0};
        // The point of the stem at x = 0.02 as the camera shows it.
        const glm::dvec3 world{0.02, 0.04, 0.005};
        const auto px = drawn_px(view, window, 0, world);
        ASSERT_TRUE(px);
        platform::PointerState was, in;
        was.window_px = in.window_px = window;
        was.cursor_px = *px + glm::dvec2{30.0, 0.0};
        in.cursor_px = *px;
        in.ray = pointer_ray(view, window, in.cursor_px);
        ASSERT_TRUE(in.ray.valid);
        const auto there = hand_onto_stem_under_cursor(in, was, false, frame, 1, yaw);
        ASSERT_TRUE(there) << "yaw " << yaw;
        // Device space: the world turned back by the camera's yaw.
        const double c = std::cos(-yaw), s = std::sin(-yaw);
        const glm::dvec3 device{c * world.x - s * world.y, s * world.x + c * world.y, world.z};
        EXPECT_LT(glm::length(*there - device), 0.006) << "yaw " << yaw;
        // A wheel notch this reading: the trainee's depth stays.
        platform::PointerState wheel = in;
        wheel.scroll = was.scroll + 1.0;
        EXPECT_FALSE(hand_onto_stem_under_cursor(wheel, was, false, frame, 1, yaw));
        // Still cursor, no press: nothing. A press: the hand goes there.
        EXPECT_FALSE(hand_onto_stem_under_cursor(in, in, false, frame, 1, yaw));
        EXPECT_TRUE(hand_onto_stem_under_cursor(in, in, true, frame, 1, yaw));
        platform::PointerState ctrl = in;
        ctrl.tilt_modifier = true;
        EXPECT_FALSE(hand_onto_stem_under_cursor(ctrl, was, false, frame, 1, yaw));
        frame.hands[1].holding = true;
        EXPECT_FALSE(hand_onto_stem_under_cursor(in, was, false, frame, 1, yaw));
    }
}
