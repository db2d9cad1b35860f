#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "components/hand.hpp"
#include "components/insertion.hpp"
#include "components/stem.hpp"
#include "engine/devices/safe_force_device.hpp"
#include "engine/devices/scripted_device.hpp"
#include "engine/sched/clocks.hpp"
#include "engine/assets/files.hpp"
#include "game/asset_paths.hpp"
#include "game/world/summary.hpp"
#include "game/world/world.hpp"
#include "scripted_hands.hpp"
#include "systems/haptics/bending_system.hpp"
#include "systems/haptics/hand_devices.hpp"
#include "systems/haptics/hand_input_system.hpp"
#include "systems/presentation/frame_channel.hpp"

using namespace ikebana;
using namespace ikebana::game;
using namespace ikebana::components;
using ikebana::test::script;

namespace {

// A sunflower lying along +x on the table (points every 11.5 mm from x = 0.1), two hands, no gravity
// tricks: the real world setup.
std::unique_ptr<World> lying_flower(glm::dvec3 base = {0.1, 0.1, 0.0}, glm::dvec3 direction = {1, 0, 0}) {
    SceneDef scene = test::kenzan_bench();
    scene.flowers.push_back({"sunflower", Placement::lying, base, glm::normalize(direction), 0.0});
    test::add_two_hands(scene, {0.1, 0.2, 0.1}, {0.2, 0.2, 0.1});
    return test::world_of(scene);
}

glm::dvec3 point(World& w, std::size_t i) { return w.sim.get<StemPoints>(w.flowers[0].entity).position_m[i]; }
ikebana::test::HandView hand(World& w, int h) { return ikebana::test::hand_view(w, static_cast<std::size_t>(h)); }

// An unplugged device: every read fails.
struct Gone : devices::HapticDevice {
    devices::DeviceCapabilities caps{"gone", false, 0.0, glm::dvec3{0.0}, true};
    const devices::DeviceCapabilities& capabilities() const override { return caps; }
    Result<devices::DeviceSample> poll(std::int64_t) override { return make_error(ErrorCode::device_error, "unplugged"); }
    Result<void> send_force(glm::dvec3) override { return make_error(ErrorCode::device_error, "unplugged"); }
};
} // namespace

TEST(TwoHands, GrabbedPointFollowsTheHandAndTheHandFeelsTheWeight) {
    auto w = lying_flower();
    const glm::dvec3 p10 = point(*w, 10);
    w->attach_device(0, script({{0.0, p10.x, p10.y, 0.05, 0}, {0.3, p10.x, p10.y, p10.z, 0}, {0.4, p10.x, p10.y, p10.z, 1},
                                {1.4, p10.x, p10.y, 0.10, 1}, {3.0, p10.x, p10.y, 0.10, 1}}));
    sched::DeterministicClock clock(w->schedule);
    clock.run_for_us(3'000'000);
    EXPECT_EQ(hand(*w, 0).held, w->flowers[0].entity);
    EXPECT_EQ(w->sim.get<Grasp>(w->flowers[0].entity).hands, 1);
    EXPECT_NEAR(point(*w, hand(*w, 0).held_point).z, 0.10 + hand(*w, 0).held_offset_m.z, 1e-9) << "the held point moves with the hand";
    EXPECT_LT(hand(*w, 0).force_n.z, -0.05) << "the hand carries part of the flower's weight (N)";
    EXPECT_GT(point(*w, 20).z, 0.0) << "the rest hangs from it";
}

// Figure 5: each hand holds a different element of one flower; pulling them apart stretches the part
// held by neither, and the restoring force pulls each hand back, in opposite directions.
TEST(TwoHands, StretchingOneFlowerPullsBothHandsTogether) {
    auto w = lying_flower();
    const glm::dvec3 a = point(*w, 5);
    const glm::dvec3 b = point(*w, 15);
    const double lift = 0.06;
    const double stretch = 0.0005;
    w->attach_device(0, script({{0.0, a.x, a.y, a.z, 1}, {0.5, a.x, a.y, lift, 1}, {2.0, a.x, a.y, lift, 1}}));
    w->attach_device(1, script({{0.0, b.x, b.y, b.z, 1}, {0.5, b.x, b.y, lift, 1}, {1.0, b.x, b.y, lift, 1},
                                {1.5, b.x + stretch, b.y, lift, 1}, {2.0, b.x + stretch, b.y, lift, 1}}));
    sched::DeterministicClock clock(w->schedule);
    clock.run_for_us(1'000'000);
    const double before = hand(*w, 1).force_n.x;
    clock.run_for_us(1'000'000);
    const auto& h0 = hand(*w, 0);
    const auto& h1 = hand(*w, 1);
    ASSERT_EQ(h0.held, h1.held) << "both hold the same flower";
    EXPECT_EQ(w->sim.get<Grasp>(w->flowers[0].entity).hands, 2);
    EXPECT_GT(h0.force_n.x, 1.0) << "the left hand is pulled towards the right (N)";
    EXPECT_LT(h1.force_n.x, -1.0) << "the right hand is pulled towards the left";
    EXPECT_NEAR(h0.force_n.x, -h1.force_n.x, 0.05 * std::abs(h1.force_n.x)) << "equal and opposite";
    EXPECT_LT(h1.force_n.x, before - 1.0) << "stretching increased the pull";
}

// A stem held at 45 degrees by two hands and lowered into the kenzan is an insertion; let go, the
// kenzan holds it.
TEST(TwoHands, HandsInsertAStemAndReleaseIt) {
    const glm::dvec3 axis = glm::normalize(glm::dvec3{1, 0, 1});
    const glm::dvec3 bottom{0.0, 0.0, 0.03};
    auto w = lying_flower(bottom, axis); // "lying" in the air: the hands catch it at once
    const glm::dvec3 p1 = point(*w, 1);
    const glm::dvec3 p8 = point(*w, 8);
    const double down = 0.026;
    w->attach_device(0, script({{0.0, p1.x, p1.y, p1.z, 1}, {1.0, p1.x, p1.y, p1.z - down, 1}, {1.2, p1.x, p1.y, p1.z - down, 0},
                                {4.0, p1.x, p1.y, 0.15, 0}}));
    w->attach_device(1, script({{0.0, p8.x, p8.y, p8.z, 1}, {1.0, p8.x, p8.y, p8.z - down, 1}, {1.2, p8.x, p8.y, p8.z - down, 0},
                                {4.0, p8.x, p8.y + 0.1, 0.15, 0}}));
    sched::DeterministicClock clock(w->schedule);
    clock.run_for_us(1'100'000);
    const auto flower = w->flowers[0].entity;
    EXPECT_EQ(w->sim.get<InsertionHistory>(flower).insertions, 1u);
    EXPECT_TRUE(w->sim.get<PinEngagement>(flower).in_kenzan);
    EXPECT_GE(w->sim.get<PinEngagement>(flower).pins.size(), 4u);
    clock.run_for_us(2'000'000);
    EXPECT_EQ(w->sim.get<Grasp>(flower).hands, 0) << "released";
    EXPECT_TRUE(w->sim.get<KenzanGrip>(flower).engaged) << "the kenzan holds what the hands let go";
    EXPECT_TRUE(w->sim.get<PinEngagement>(flower).in_kenzan);
}

// Unplugging a device mid-session releases what that hand held and zeroes its force; the world runs
// on; plugging it back re-attaches the hand.
TEST(TwoHands, UnpluggedDeviceReleasesAndReattaches) {
    auto w = lying_flower();
    const glm::dvec3 p10 = point(*w, 10);
    w->attach_device(0, script({{0.0, p10.x, p10.y, p10.z, 1}, {0.5, p10.x, p10.y, 0.06, 1}, {5.0, p10.x, p10.y, 0.06, 1}}));
    sched::DeterministicClock clock(w->schedule);
    clock.run_for_us(600'000);
    ASSERT_FALSE(hand(*w, 0).held.is_null());
    w->attach_device(0, std::make_unique<Gone>());
    clock.run_for_us(500'000);
    EXPECT_FALSE(hand(*w, 0).connected);
    EXPECT_TRUE(hand(*w, 0).held.is_null()) << "what it held was released";
    EXPECT_EQ(hand(*w, 0).force_n, glm::dvec3(0.0));
    EXPECT_EQ(hand(*w, 0).disconnects, 1u);
    EXPECT_LT(point(*w, 10).z, 0.02) << "and fell";
    w->attach_device(0, script({{0.0, p10.x, p10.y, 0.05, 0}, {5.0, p10.x, p10.y, 0.05, 0}}));
    clock.run_for_us(100'000);
    EXPECT_TRUE(hand(*w, 0).connected) << "plugged back in";
}

TEST(TwoHands, HandCannotGoThroughTheTable) {
    auto w = lying_flower();
    w->attach_device(0, script({{0.0, 0.3, 0.3, 0.05, 0}, {0.5, 0.3, 0.3, -0.05, 0}, {1.0, 0.3, 0.3, -0.05, 0}}));
    sched::DeterministicClock clock(w->schedule);
    clock.run_for_us(1'000'000);
    EXPECT_NEAR(hand(*w, 0).proxy_m.z, 0.01, 1e-12) << "the cube rests on the table (half its 20 mm edge)";
    EXPECT_NEAR(hand(*w, 0).device_m.z, -0.05, 1e-9);
    EXPECT_NEAR(hand(*w, 0).force_n.z, 400.0 * 0.06, 1e-6) << "the coupling spring pushes the hand back up";
}

// Every device sample recorded with its time, replayed on the deterministic clock: the same world.
TEST(TwoHands, ReplayedSessionGivesTheSameWorldHash) {
    const auto make_live = [] {
        auto w = lying_flower();
        const glm::dvec3 a = point(*w, 5);
        const glm::dvec3 b = point(*w, 15);
        w->attach_device(0, script({{0.0, a.x, a.y, a.z + 0.02, 0}, {0.3, a.x, a.y, a.z, 0}, {0.35, a.x, a.y, a.z, 1},
                                    {1.0, a.x + 0.01, a.y, 0.07, 1}, {1.6, a.x, a.y + 0.02, 0.05, 0}}));
        w->attach_device(1, script({{0.0, b.x, b.y, b.z, 1}, {0.8, b.x + 0.002, b.y, 0.06, 1}, {1.6, b.x, b.y, 0.06, 1}}));
        return w;
    };
    std::ostringstream left_file;
    std::ostringstream right_file;
    devices::DeviceRecorder left(left_file, AsyncLineWriter::WhenFull::wait);
    devices::DeviceRecorder right(right_file, AsyncLineWriter::WhenFull::wait);
    auto live = make_live();
    live->sim.resource<systems::HandDevices>()->record_to(0, &left);
    live->sim.resource<systems::HandDevices>()->record_to(1, &right);
    sched::DeterministicClock live_clock(live->schedule);
    live_clock.run_for_us(2'000'000);
    left.flush();
    right.flush();

    auto replay = lying_flower();
    for (int h = 0; h < 2; ++h) {
        auto keys = devices::parse_trajectory(h == 0 ? left_file.str() : right_file.str(), "session");
        ASSERT_TRUE(keys) << keys.error().message;
        replay->attach_device(static_cast<std::uint8_t>(h),
                              std::make_unique<devices::ScriptedDevice>(std::move(keys).value(), devices::ScriptedDevice::Mode::replay));
    }
    sched::DeterministicClock replay_clock(replay->schedule);
    replay_clock.run_for_us(2'000'000);
    EXPECT_EQ(replay->state_hash(), live->state_hash());
    EXPECT_NE(hand(*live, 0).held_point, hand(*live, 1).held_point) << "the session did something";
}

namespace {
// Two hands, tips together, hold a cherry branch lying on the table, lift it, and roll the left device
// by `roll` radians to bend it; then let go.
struct BendRun {
    std::unique_ptr<World> w;
    std::vector<glm::dvec2> rest_bends_before;
    Bending during{};
    glm::dvec3 left_force{0.0};
    glm::dvec3 right_force{0.0};
};
// Each hinge's rest bend as a vector in its frame (angle times direction): the natural curve's and a
// permanent set's add as vectors, so the set is how far these moved.
std::vector<glm::dvec2> rest_bends(World& w) {
    const auto& rest = w.sim.get<StemRestShape>(w.flowers[0].entity);
    std::vector<glm::dvec2> bends;
    for (std::size_t i = 0; i < rest.hinge_angle_rad.size(); ++i) bends.push_back(rest.hinge_angle_rad[i] * rest.hinge_bend_direction[i]);
    return bends;
}
double set_between(const std::vector<glm::dvec2>& before, const std::vector<glm::dvec2>& after) {
    double set = 0.0;
    for (std::size_t i = 0; i < before.size() && i < after.size(); ++i) set += glm::length(after[i] - before[i]);
    return set;
}
// The shipped cherry without its twigs (a stem the bend law's figures are exactly about: twigs roll a
// lying branch off the plane its natural curve lies in).
std::string bare_cherry() {
    const auto text = assets::read_text_file(asset_dir() / "species" / "cherry_branch.json");
    EXPECT_TRUE(text.ok());
    auto json = nlohmann::json::parse(text.ok() ? *text : std::string("{}"));
    json.erase("branches");
    const auto path = std::filesystem::temp_directory_path() / "ikebana-two-hands-cherry_branch.json";
    EXPECT_TRUE(assets::write_text_file(path, json.dump(1)).ok());
    return path.string();
}

// A cherry branch lying on the table, and two hands above it.
std::unique_ptr<World> branch_and_two_hands() {
    SceneDef scene = test::kenzan_bench();
    scene.flowers.push_back({bare_cherry(), Placement::lying, {0.1, 0.1, 0.0}, {1, 0, 0}, 0.0});
    test::add_two_hands(scene, {0.1, 0.2, 0.1}, {0.2, 0.2, 0.1});
    return test::world_of(scene);
}
BendRun bend_branch(double roll, double roll_at_start = 0.0) {
    BendRun run;
    run.w = branch_and_two_hands();
    auto& w = *run.w;
    const glm::dvec3 a = point(w, 11);
    const glm::dvec3 b = point(w, 13);
    auto script6 = [](glm::dvec3 p, double roll_from, double roll_to) {
        std::ostringstream csv;
        csv << "time_s,x_m,y_m,z_m,rx_rad,ry_rad,rz_rad,buttons\n"
            << "0," << p.x << "," << p.y << "," << p.z << "," << roll_from << ",0,0,1\n"
            << "0.5," << p.x << "," << p.y << ",0.1," << roll_from << ",0,0,1\n"
            << "1.0," << p.x << "," << p.y << ",0.1," << roll_to << ",0,0,1\n"
            << "2.0," << p.x << "," << p.y << ",0.1," << roll_to << ",0,0,1\n"
            << "2.1," << p.x << "," << p.y << ",0.1," << roll_from << ",0,0,0\n";
        return std::make_unique<devices::ScriptedDevice>(*devices::parse_trajectory(csv.str(), "bend"), devices::ScriptedDevice::Mode::interpolate);
    };
    w.attach_device(0, script6(a, roll_at_start, roll_at_start + roll));
    w.attach_device(1, script6(b, 0.0, 0.0));
    run.rest_bends_before = rest_bends(w);
    sched::DeterministicClock clock(w.schedule);
    clock.run_for_us(1'500'000);
    run.during = w.sim.get<Bending>(w.flowers[0].entity);
    run.left_force = hand(w, 0).force_n;
    run.right_force = hand(w, 1).force_n;
    clock.run_for_us(2'000'000);
    return run;
}
} // namespace

// Two fists on one stem hold its bark: lifted by two points 117 mm apart (too far apart to bend it), a
// twisting moment on its top segment (a tool turning it, a twig's weight) twists the part beyond the
// upper hand, not the stem between the hands: the bark under each fist stays where it is. (Held by two
// points alone, nothing held the frame, and the whole stem spun about its axis.)
TEST(TwoHands, TwoHandsHoldTheBarkAgainstATwistingMoment) {
    auto w = branch_and_two_hands();
    const glm::dvec3 a = point(*w, 1);
    const glm::dvec3 b = point(*w, 9);
    ASSERT_GT(glm::length(b - a), 0.1);
    auto lift = [](glm::dvec3 p) {
        std::ostringstream csv;
        csv << "time_s,x_m,y_m,z_m,rx_rad,ry_rad,rz_rad,buttons\n"
            << "0," << p.x << "," << p.y << "," << p.z << ",0,0,0,1\n"
            << "0.5," << p.x << "," << p.y << ",0.12,0,0,0,1\n"
            << "3.0," << p.x << "," << p.y << ",0.12,0,0,0,1\n";
        return std::make_unique<devices::ScriptedDevice>(*devices::parse_trajectory(csv.str(), "lift"), devices::ScriptedDevice::Mode::interpolate);
    };
    w->attach_device(0, lift(a));
    w->attach_device(1, lift(b));
    sched::DeterministicClock clock(w->schedule);
    clock.run_for_us(800'000);
    const ecs::Entity e = w->flowers[0].entity;
    ASSERT_TRUE(hand(*w, 0).held == e && hand(*w, 1).held == e) << "both hands hold it";
    ASSERT_FALSE(w->sim.get<Bending>(e).active) << "too far apart to bend it";
    const std::size_t middle = 5; // between the hands
    const glm::dvec3 before = w->sim.get<StemFrame>(e).director[middle];
    for (int t = 0; t < 500; ++t) {
        auto& f = w->sim.get<StemFrame>(e);
        f.external_twist_nm.back() = 0.002; // 2 mN m on the top segment, every tick for half a second
        clock.run_for_us(1000);
    }
    const auto& x = w->sim.get<StemPoints>(e).position_m;
    const glm::dvec3 axis = glm::normalize(x[middle + 1] - x[middle]);
    const glm::dvec3 now = w->sim.get<StemFrame>(e).director[middle];
    const double turned = std::atan2(glm::dot(glm::cross(before, now), axis), glm::dot(before, now));
    EXPECT_LT(std::abs(turned), 2.0 * M_PI / 180.0) << "the bark between the hands turned " << turned * 180.0 / M_PI << " degrees";
}

// Figures 6-8 as a gesture: the stem between the supports takes Eq. 4's shape and both hands feel F^b.
TEST(TwoHands, BendingFeedsEq5BackToBothHands) {
    auto run = bend_branch(0.5);
    ASSERT_TRUE(run.during.active);
    EXPECT_NEAR(run.during.theta_rad, M_PI - 0.5, 1e-9);
    const double ei = 6e9 * M_PI * std::pow(0.008, 4) / 64.0;
    EXPECT_NEAR(run.during.force_n, 24.0 * ei / (run.during.span_m * run.during.span_m * std::tan(0.5 * run.during.theta_rad)),
                1e-6 * run.during.force_n);
    EXPECT_LT(glm::dot(run.left_force, run.during.push_direction), 0.0) << "pushed back against the thumbs";
    EXPECT_LT(glm::dot(run.right_force, run.during.push_direction), 0.0);
}

// Bent 0.5 rad (28.6 degrees) against a 12-degree threshold: 16.6 degrees stay after release.
TEST(TwoHands, BendingPastTheThresholdLeavesAPermanentSet) {
    auto run = bend_branch(0.5);
    const double set = set_between(run.rest_bends_before, rest_bends(*run.w));
    EXPECT_NEAR(set, 0.5 - 12.0 * M_PI / 180.0, 1e-6);
    EXPECT_FALSE(run.w->sim.get<Bending>(run.w->flowers[0].entity).active) << "released";
    auto gentle = bend_branch(0.15); // 8.6 degrees: springs back
    EXPECT_NEAR(set_between(gentle.rest_bends_before, rest_bends(*gentle.w)), 0.0, 1e-12);
}

// Two devices are never held at the same roll: a second hand that takes the stem rolled two radians
// from the first does not bend it two radians in a tick (that flung a cherry branch kilometres). The
// bend counts from the rolls the hands had when they came together, and follows them at a wrist's pace.
TEST(TwoHands, ABendCountsFromTheWristsAsTheyCameTogether) {
    auto run = bend_branch(0.5, 2.0);
    ASSERT_TRUE(run.during.active);
    EXPECT_NEAR(run.during.theta_rad, M_PI - 0.5, 1e-9) << "rolled 0.5 rad since the hands came together";
    const double set = set_between(run.rest_bends_before, rest_bends(*run.w));
    EXPECT_NEAR(set, 0.5 - 12.0 * M_PI / 180.0, 1e-6);
    for (const auto& x : run.w->sim.get<StemPoints>(run.w->flowers[0].entity).position_m) {
        EXPECT_LT(glm::length(x - glm::dvec3{0.1, 0.1, 0.0}), 0.5) << "the branch stays within reach";
    }
}

TEST(TwoHands, ABendFollowsTheWristsAtAWristsPace) {
    // The left device's reading jumps a whole radian between two ticks (a gimbal's glitch, a dropped
    // packet): the stem is bent at max_bend_rad_s toward it, not at once.
    auto w = branch_and_two_hands();
    const glm::dvec3 a = point(*w, 11), b = point(*w, 13);
    auto device = [](glm::dvec3 p, double jump_to) {
        std::ostringstream csv;
        csv << "time_s,x_m,y_m,z_m,rx_rad,ry_rad,rz_rad,buttons\n"
            << "0," << p.x << "," << p.y << "," << p.z << ",0,0,0,1\n"
            << "0.5," << p.x << "," << p.y << ",0.1,0,0,0,1\n"
            << "0.6," << p.x << "," << p.y << ",0.1,0,0,0,1\n"
            << "0.601," << p.x << "," << p.y << ",0.1," << jump_to << ",0,0,1\n"
            << "2.0," << p.x << "," << p.y << ",0.1," << jump_to << ",0,0,1\n";
        return std::make_unique<devices::ScriptedDevice>(*devices::parse_trajectory(csv.str(), "jump"), devices::ScriptedDevice::Mode::interpolate);
    };
    w->attach_device(0, device(a, 1.0));
    w->attach_device(1, device(b, 0.0));
    sched::DeterministicClock clock(w->schedule);
    clock.run_for_us(611'000);
    const systems::BendingSystem bending;
    const auto& during = w->sim.get<Bending>(w->flowers[0].entity);
    ASSERT_TRUE(during.active);
    EXPECT_LE(M_PI - during.theta_rad, bending.max_bend_rad_s * 0.011 + 1e-9) << "10 ms after the jump";
    EXPECT_GT(M_PI - during.theta_rad, 0.0);
    clock.run_for_us(600'000);
    EXPECT_NEAR(w->sim.get<Bending>(w->flowers[0].entity).theta_rad, M_PI - 1.0, 1e-9) << "caught up";
}

// The main lane hears of it when a device goes away and when it comes back.
TEST(TwoHands, UnpluggingIsAnnouncedWhenItHappens) {
    auto w = lying_flower();
    std::vector<std::string> heard;
    w->main.resource<systems::ReceivedFrames>()->announce = [&](const std::string& m) { heard.push_back(m); };
    const glm::dvec3 p = point(*w, 10);
    w->attach_device(0, script({{0.0, p.x, p.y, 0.05, 0}, {5.0, p.x, p.y, 0.05, 0}}));
    sched::DeterministicClock clock(w->schedule);
    clock.run_for_us(300'000);
    EXPECT_TRUE(heard.empty());
    w->attach_device(0, std::make_unique<Gone>());
    clock.run_for_us(200'000);
    ASSERT_EQ(heard.size(), 1u);
    EXPECT_NE(heard[0].find("left hand: device unplugged"), std::string::npos);
    w->attach_device(0, script({{0.0, p.x, p.y, 0.05, 0}, {5.0, p.x, p.y, 0.05, 0}}));
    clock.run_for_us(200'000);
    ASSERT_EQ(heard.size(), 2u);
    EXPECT_NE(heard[1].find("left hand: device back"), std::string::npos);
}

// One hand on a flower holds its direction (two points); a second hand on it makes each hold one
// point; when one lets go, the other takes the direction the two left it in.
TEST(TwoHands, AGripHoldsTheDirectionOnlyWhileItIsAlone) {
    auto w = lying_flower();
    const glm::dvec3 a = point(*w, 5);
    w->attach_device(0, script({{0.0, a.x, a.y, a.z, 1}, {0.5, a.x, a.y, 0.06, 1}, {3.0, a.x, a.y, 0.06, 1}}));
    sched::DeterministicClock clock(w->schedule);
    clock.run_for_us(600'000);
    ASSERT_EQ(hand(*w, 0).held, w->flowers[0].entity);
    EXPECT_TRUE(hand(*w, 0).holds_direction);
    const auto second = hand(*w, 0).second_point;
    EXPECT_TRUE(second == 4 || second == 6) << "a neighbour of the held point " << second;
    EXPECT_EQ(w->sim.get<StemPoints>(w->flowers[0].entity).pinned[second], 1);

    // The right hand reaches the stem where it now is, and grabs it.
    const glm::dvec3 b_now = point(*w, 15);
    w->attach_device(1, script({{0.6, b_now.x, b_now.y, b_now.z, 0}, {0.7, b_now.x, b_now.y, b_now.z, 1}, {1.5, b_now.x, b_now.y, b_now.z, 1},
                                {1.6, b_now.x, b_now.y, b_now.z, 0}, {3.0, b_now.x, b_now.y + 0.1, b_now.z, 0}}));
    clock.run_for_us(400'000);
    ASSERT_EQ(hand(*w, 1).held, w->flowers[0].entity);
    EXPECT_FALSE(hand(*w, 0).holds_direction) << "two hands: one point each";
    EXPECT_FALSE(hand(*w, 1).holds_direction);
    EXPECT_EQ(w->sim.get<StemPoints>(w->flowers[0].entity).pinned[second], 0) << "the second point is let go";

    clock.run_for_us(1'000'000); // the right hand lets go
    EXPECT_TRUE(hand(*w, 1).held.is_null());
    EXPECT_TRUE(hand(*w, 0).holds_direction) << "alone again: the left hand holds the direction";
    EXPECT_GT(point(*w, 20).z, 0.03) << "and the far end stays up instead of hanging";
}

// The camera turned a quarter round (the view channel, written by the app's main thread): the device's
// "right" moves the hand along the turned axis, so that it is still the viewer's right.
TEST(TwoHands, TheWorkspaceTurnsWithTheView) {
    auto w = lying_flower();
    w->attach_device(0, script({{0.0, 0.05, 0.0, 0.1, 0}, {0.1, 0.05, 0.0, 0.1, 0}, {0.3, 0.07, 0.0, 0.1, 0}, {1.0, 0.07, 0.0, 0.1, 0}}));
    w->view.yaw_rad.store(M_PI / 2);
    sched::DeterministicClock clock(w->schedule);
    clock.run_for_us(100'000);
    const glm::dvec3 before = hand(*w, 0).device_m;
    clock.run_for_us(400'000);
    const glm::dvec3 moved = hand(*w, 0).device_m - before;
    EXPECT_NEAR(moved.x, 0.0, 1e-9);
    EXPECT_NEAR(moved.y, 0.02, 1e-9) << "device +x is world +y after a quarter turn";
    EXPECT_NEAR(w->sim.get<WorkspaceMapping>(w->hands[0]).yaw_rad, M_PI / 2, 1e-12);
}

// A violent script (1.3 m per tick while holding) once drove the held stem's energy to tens of kJ, and
// a scripted hand's force skipped the safety chain. Now the held hand follows at a hand's speed, and
// the force passes the chain on the script's own time, so a run shows what a device would feel.
TEST(TwoHands, AViolentScriptedHandIsFollowedAtAHandsSpeedAndItsForceIsMadeSafe) {
    auto w = lying_flower();
    const glm::dvec3 p10 = point(*w, 10);
    // Free above the stem for the first 0.1 s (the chain engages once the force asked has been small for
    // a moment), then it comes down, takes the stem and lifts it.
    std::vector<ikebana::test::Key> keys{{0.0, p10.x, p10.y, p10.z + 0.05, 0}, {0.1, p10.x, p10.y, p10.z + 0.05, 0}, {0.15, p10.x, p10.y, p10.z, 0},
                                         {0.151, p10.x, p10.y, p10.z, 1},
                                         {0.5, p10.x, p10.y, 0.06, 1}};
    for (int k = 1; k <= 300; ++k) keys.push_back({0.5 + 0.001 * k, k % 2 ? 0.65 : -0.65, p10.y, 0.06, 1});
    w->attach_device(0, script(keys));
    const auto* safe = dynamic_cast<const devices::SafeForceDevice*>(w->hand_devices[0].get());
    ASSERT_NE(safe, nullptr) << "a scripted hand gets the safety chain too";
    sched::DeterministicClock clock(w->schedule);
    clock.run_for_us(500'000);
    ASSERT_FALSE(hand(*w, 0).held.is_null());
    glm::dvec3 last = hand(*w, 0).proxy_m;
    double fastest = 0.0;
    for (int tick = 0; tick < 300; ++tick) {
        clock.run_for_us(1'000);
        fastest = std::max(fastest, glm::length(hand(*w, 0).proxy_m - last));
        last = hand(*w, 0).proxy_m;
    }
    EXPECT_LE(fastest, systems::max_hand_speed_m_s * 0.001 + 1e-12) << "the held hand moves no faster than a hand";
    const auto summary = summarize(*w);
    EXPECT_LT(summary.flower_states[0].elastic_j, summary.flower_states[0].elastic_ceiling_j) << "the stem's energy stays physical";
    EXPECT_LT(summary.kinetic_j, 10.0);
    EXPECT_LE(safe->peak_output_n(), 3.0 + 1e-9);
    EXPECT_GT(safe->counters().rate_limited, 0u) << "the chain limited the steps the script asked for";
}

// Pushing a stem back in by jerks (a mouse moving 1.25 cm a frame at 10 frames a second) bounces its
// bottom off the pin tips before it goes in: that is one insertion, not two. The same push made
// smoothly, or in jerks 16 ms apart, counts the same.
TEST(TwoHands, AStemPushedInByJerksIsOneInsertion) {
    for (const double frame_s : {0.016, 0.1, 0.2}) {
        auto scene = load_scene(std::string(IKEBANA_ASSET_DIR) + "/scenes/default.json");
        ASSERT_TRUE(scene);
        auto world = World::create(*scene);
        ASSERT_TRUE(world);
        World& w = **world;
        // The right hand onto the settled sunflower at 2 s, up 5 cm, right 1.9 cm, down 5 cm, let go.
        const double x0 = 0.06 + 61.0 / 640.0 * 0.30, z0 = 0.12 - 37.0 / 360.0 * 0.25;
        const auto clamp_steps = [](int f, int a, int b) { return static_cast<double>(std::clamp(f, a, b) - a); };
        std::vector<ikebana::test::Key> keys{{0.0, 0.06, 0.0, 0.12, 0}};
        ikebana::test::Key previous{};
        for (int f = 0; f < 45; ++f) {
            const double t = 2.0 + f * frame_s;
            const ikebana::test::Key now{t, x0 + 20.0 * clamp_steps(f, 8, 10) / 640.0 * 0.30, 0.0,
                                         z0 + (18.0 * clamp_steps(f, 3, 7) - 18.0 * clamp_steps(f, 11, 15)) / 360.0 * 0.25, f >= 1 && f < 20 ? 1 : 0};
            if (f > 0) keys.push_back({t - 0.0005, previous.x, previous.y, previous.z, previous.buttons}); // a jump, not a glide
            keys.push_back(now);
            previous = now;
        }
        w.attach_device(1, script(keys));
        sched::DeterministicClock clock(w.schedule);
        clock.run_for_us(static_cast<std::int64_t>((2.0 + 50 * frame_s + 2.0) * 1e6));
        const auto& history = w.sim.get<InsertionHistory>(w.flowers[0].entity);
        EXPECT_EQ(history.insertions, 1u) << frame_s << " s a frame";
        EXPECT_TRUE(w.sim.get<PinEngagement>(w.flowers[0].entity).in_kenzan) << frame_s << " s a frame";
    }
}
