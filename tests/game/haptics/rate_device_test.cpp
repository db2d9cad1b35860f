#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "components/hand.hpp"
#include "components/stem.hpp"
#include "engine/sched/clocks.hpp"
#include "game/world/world.hpp"
#include "scripted_hands.hpp"
#include "systems/haptics/hand_input_system.hpp"

using namespace ikebana;
using namespace ikebana::game;
using namespace ikebana::components;

namespace {

// A rate device (a SpaceMouse) whose push and twist the test sets: normalised, [-1, 1].
struct RateDevice final : devices::HapticDevice {
    devices::DeviceCapabilities caps{"a rate device", false, 0.0, glm::dvec3{0.0}, false};
    glm::dvec3 push{0.0}, twist{0.0};
    std::uint32_t buttons = 0;
    const devices::DeviceCapabilities& capabilities() const override { return caps; }
    Result<devices::DeviceSample> poll(std::int64_t now_us) override { return devices::DeviceSample{now_us, push, twist, buttons}; }
    Result<void> send_force(glm::dvec3) override { return {}; }
};

std::unique_ptr<World> lying_flower() {
    SceneDef scene = test::kenzan_bench();
    scene.flowers.push_back({"sunflower", Placement::lying, {0.1, 0.1, 0.0}, {1, 0, 0}, 0.0});
    test::add_two_hands(scene, {-0.1, 0.2, 0.1}, {0.2, 0.2, 0.1});
    return test::world_of(scene);
}

// The held stem's direction in the table's plane (radians about the vertical).
double heading(World& w) {
    const auto& x = w.sim.get<StemPoints>(w.flowers[0].entity).position_m;
    const glm::dvec3 d = x.back() - x.front();
    return std::atan2(d.y, d.x);
}

} // namespace

TEST(RateDevice, ATwistTurnsTheHandAtItsRateAndTheTurnStaysWhenTheCapIsLetGo) {
    auto w = lying_flower();
    auto device = std::make_unique<RateDevice>();
    RateDevice& cap = *device;
    w->attach_device(1, std::move(device));
    sched::DeterministicClock clock(w->schedule);
    const double rate = w->sim.get<WorkspaceMapping>(w->hands[1]).rate_turn_rad_s;
    cap.twist = {0.0, 0.0, 0.5};
    clock.run_for_us(1'000'000);
    const double turned = w->sim.get<HandInput>(w->hands[1]).rotation_rad.z;
    EXPECT_NEAR(turned, 0.5 * rate, 0.01 * rate) << "half a twist for a second turns half the rate";
    cap.twist = glm::dvec3{0.0};
    clock.run_for_us(1'000'000);
    EXPECT_DOUBLE_EQ(w->sim.get<HandInput>(w->hands[1]).rotation_rad.z, turned) << "let go, the cap springs back; the hand stays turned";
}

TEST(RateDevice, ACapAtRestBelowTheDeadZoneTurnsNothing) {
    auto w = lying_flower();
    auto device = std::make_unique<RateDevice>();
    device->twist = {0.5 * systems::rate_dead_zone, -0.5 * systems::rate_dead_zone, 0.9 * systems::rate_dead_zone};
    w->attach_device(1, std::move(device));
    sched::DeterministicClock clock(w->schedule);
    clock.run_for_us(3'000'000);
    EXPECT_EQ(w->sim.get<HandInput>(w->hands[1]).rotation_rad, glm::dvec3{0.0});
}

TEST(RateDevice, AStemHeldByATwistedSpaceMouseTurnsWithItAndStaysTurned) {
    auto w = lying_flower();
    auto device = std::make_unique<RateDevice>();
    RateDevice& cap = *device;
    w->attach_device(1, std::move(device));
    sched::DeterministicClock clock(w->schedule);
    // Push the hand from where it starts onto the stem's 10th point, at the rate's own speed.
    const glm::dvec3 p10 = w->sim.get<StemPoints>(w->flowers[0].entity).position_m[10];
    const double speed = w->sim.get<WorkspaceMapping>(w->hands[1]).rate_speed_m_s;
    for (int i = 0; i < 4000; ++i) {
        const glm::dvec3 to = p10 + glm::dvec3{0, 0, 0.005} - w->sim.get<HandInput>(w->hands[1]).device_m;
        cap.push = glm::clamp(to / (speed * 0.05), glm::dvec3{-1.0}, glm::dvec3{1.0});
        clock.run_for_us(1000);
    }
    cap.push = glm::dvec3{0.0};
    cap.buttons = 1;
    clock.run_for_us(100'000);
    ASSERT_EQ(w->sim.get<HandGrip>(w->hands[1]).held, w->flowers[0].entity) << "the hand took the stem";
    cap.push = {0.0, 0.0, 0.3};
    clock.run_for_us(300'000);
    cap.push = glm::dvec3{0.0};
    const double before = heading(*w);
    cap.twist = {0.0, 0.0, 1.0};
    clock.run_for_us(500'000);
    cap.twist = glm::dvec3{0.0};
    clock.run_for_us(1'000'000);
    const double rate = w->sim.get<WorkspaceMapping>(w->hands[1]).rate_turn_rad_s;
    EXPECT_NEAR(heading(*w) - before, 0.5 * rate, 0.15) << "the stem turned about the vertical with the hand, and stayed";
}
