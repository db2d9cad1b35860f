#include <gtest/gtest.h>

#include "components/hand.hpp"
#include "components/insertion.hpp"
#include "components/stem.hpp"
#include "engine/devices/mouse_keyboard_device.hpp"
#include "engine/devices/scripted_device.hpp"
#include "engine/sched/clocks.hpp"
#include "game/world/world.hpp"
#include "scripted_hands.hpp"

using namespace ikebana;
using namespace ikebana::game;
using namespace ikebana::components;
using ikebana::test::script;

namespace {

// The default scene's sunflower, standing in the kenzan at 30 degrees from the vertical.
std::unique_ptr<World> standing_sunflower() {
    SceneDef scene = test::kenzan_bench();
    scene.flowers.push_back({"sunflower", Placement::inserted, {-0.006, 0.0, 0.010}, glm::normalize(glm::dvec3{0.5, 0.0, 0.866}), 0.013});
    test::add_two_hands(scene, {-0.12, -0.06, 0.15}, {0.12, -0.06, 0.15});
    return test::world_of(scene);
}

glm::dvec3 point(World& w, std::size_t i) { return w.sim.get<StemPoints>(w.flowers[0].entity).position_m[i]; }
} // namespace

// One hand, as with the mouse: grab the stem halfway up, pull it out, carry it 2 cm aside, push it
// back in and let go. A grip holds the stem's direction as well as its place, so the heavy head does
// not swing the bottom away from the pins.
TEST(OneHand, PullsAStemOutAndInsertsItElsewhere) {
    auto w = standing_sunflower();
    const auto flower = w->flowers[0].entity;
    sched::DeterministicClock clock(w->schedule);
    clock.run_for_us(2'000'000); // let it settle in the kenzan
    const glm::dvec3 grip = point(*w, 10);
    const double lift = 0.045;
    const double aside = 0.02;
    w->attach_device(1, script({{2.0, grip.x + 0.03, grip.y, grip.z, 0}, {2.5, grip.x, grip.y, grip.z, 0}, {2.6, grip.x, grip.y, grip.z, 1},
                                {3.6, grip.x, grip.y, grip.z + lift, 1}, {4.4, grip.x, grip.y + aside, grip.z + lift, 1},
                                {5.6, grip.x, grip.y + aside, grip.z, 1}, {5.8, grip.x, grip.y + aside, grip.z, 0},
                                {6.4, grip.x + 0.05, grip.y + aside, grip.z, 0}, {9.0, grip.x + 0.05, grip.y + aside, grip.z, 0}}));
    const glm::dvec3 axis_before = glm::normalize(point(*w, 20) - point(*w, 0));
    clock.run_for_us(1'600'000); // grabbed and lifted
    ASSERT_EQ(ikebana::test::hand_view(*w, 1).held, flower);
    EXPECT_TRUE(ikebana::test::hand_view(*w, 1).holds_direction);
    EXPECT_FALSE(w->sim.get<PinEngagement>(flower).in_kenzan) << "pulled out";
    const glm::dvec3 axis_lifted = glm::normalize(point(*w, 20) - point(*w, 0));
    EXPECT_GT(glm::dot(axis_before, axis_lifted), std::cos(0.05)) << "the grip keeps the stem's direction: the head does not swing down";
    EXPECT_GT(point(*w, 20).z, point(*w, 0).z + 0.1);

    clock.run_for_us(2'400'000); // carried aside, pushed in, let go
    const auto& hand = ikebana::test::hand_view(*w, 1);
    EXPECT_TRUE(hand.held.is_null()) << "released";
    EXPECT_EQ(w->sim.get<StemPoints>(flower).pinned, std::vector<std::uint8_t>(21, 0)) << "nothing stays pinned after letting go";
    EXPECT_EQ(w->sim.get<InsertionHistory>(flower).insertions, 1u) << "pushing it back in is an insertion";
    const auto& engagement = w->sim.get<PinEngagement>(flower);
    EXPECT_TRUE(engagement.in_kenzan);
    EXPECT_GE(engagement.pins.size(), 4u);
    EXPECT_NEAR(point(*w, 0).y, aside, 0.004) << "in its new place, one pin pitch at most from where the hand put it";

    clock.run_for_us(3'000'000); // the hand moves away; the kenzan holds the flower
    EXPECT_TRUE(w->sim.get<KenzanGrip>(flower).engaged);
    EXPECT_TRUE(w->sim.get<PinEngagement>(flower).in_kenzan);
    EXPECT_EQ(w->sim.get<InsertionHistory>(flower).insertions, 1u);
}

namespace {
struct StepPointer : platform::PointerSource {
    platform::PointerState state = [] {
        platform::PointerState s;
        s.cursor_px = {320.0, 180.0};
        s.window_px = {640.0, 360.0};
        return s;
    }();
    platform::PointerState read() override { return state; }
};
} // namespace

// The same with the mouse, whose position reaches the simulation in frame-sized steps (30 Hz): the
// grab's pull that unbends the standing stem is no insertion, the push back in is one.
TEST(OneHand, TheMouseReinsertsTheStemInFrameSizedSteps) {
    auto w = standing_sunflower();
    StepPointer pointer;
    devices::MouseKeyboardHands mouse(pointer);
    w->attach_device(0, mouse.hand(0));
    w->attach_device(1, mouse.hand(1)); // the right hand is active, on the stem at (60, 0, 120) mm
    const auto flower = w->flowers[0].entity;
    const glm::dvec3 bottom_before = point(*w, 0);
    sched::DeterministicClock clock(w->schedule);
    auto frame = [&](int n) {
        auto& s = pointer.state;
        if (n == 3) s.grab_button = true;
        if (n >= 5 && n < 9) s.cursor_px.y -= 18.0;   // up 5 cm
        if (n >= 10 && n < 12) s.cursor_px.x += 20.0; // right 1.9 cm
        if (n >= 13 && n < 17) s.cursor_px.y += 18.0; // down 5 cm
        if (n == 22) s.grab_button = false;
        clock.run_for_us(33'333);
    };
    for (int n = 0; n < 10; ++n) frame(n);
    EXPECT_TRUE(ikebana::test::hand_view(*w, 1).holds_direction);
    EXPECT_FALSE(w->sim.get<PinEngagement>(flower).in_kenzan) << "out";
    EXPECT_EQ(w->sim.get<InsertionHistory>(flower).insertions, 0u) << "pulling out is not an insertion";
    for (int n = 10; n < 44; ++n) frame(n);
    EXPECT_TRUE(ikebana::test::hand_view(*w, 1).held.is_null());
    EXPECT_EQ(w->sim.get<InsertionHistory>(flower).insertions, 1u);
    EXPECT_TRUE(w->sim.get<PinEngagement>(flower).in_kenzan);
    EXPECT_NEAR(point(*w, 0).x - bottom_before.x, 40.0 / 640.0 * 0.30, 0.006) << "where the mouse put it";
}
