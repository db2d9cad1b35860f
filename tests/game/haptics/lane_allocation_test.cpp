// Nothing on the 1 kHz lane allocates in a steady tick, whatever state its force device is in:
// glibc's allocator locks do not inherit priority, so a malloc there can wait on a normal-priority
// thread. Counted with a replaced operator new (tests/support/allocation_counter.cpp) while the "sim"
// lane's systems run, over 1,000 ticks of the Sogetsu lesson scene, with a DIY device behind the real
// HID transport (hidapi shimmed) connected, silent, lost, unplugged and sending reports it refuses.
#include <gtest/gtest.h>

#include <chrono>
#include <memory>
#include <thread>

#include "engine/devices/hid_devices.hpp"
#include "engine/devices/hid_transport.hpp"
#include "engine/devices/reconnecting_device.hpp"
#include "engine/devices/safe_force_device.hpp"
#include "engine/ecs/registry.hpp"
#include "engine/sched/clocks.hpp"
#include "engine/sched/schedule.hpp"
#include "game/scene/scene.hpp"
#include "game/world/world.hpp"
#include "systems/haptics/hand_devices.hpp"
#include "tests/support/allocation_counter.hpp"
#include "tests/support/hidapi_shim.hpp"
#include "components/insertion.hpp"
#include "components/stem.hpp"
#include "components/flower.hpp"
#include "engine/ecs/hierarchy.hpp"
#include "scripted_hands.hpp"
#include "systems/insertion/pruning_system.hpp"
#include "systems/haptics/trainee_command_system.hpp"

using namespace ikebana;
using namespace ikebana::game;
using ikebana::test::ShimDevice;

namespace {

enum class DeviceState { connected, silent, lost, unplugged, refusing };

struct Counted {
    std::uint64_t allocations = 0;
    std::string where;
    bool reached_state = false;
};

// Paced to the wall clock, a millisecond a tick, as the device's silence is judged on it.
void run_paced(sched::DeterministicClock& clock, int ticks) {
    auto next = std::chrono::steady_clock::now();
    for (int i = 0; i < ticks; ++i) {
        clock.run_for_us(1000);
        next += std::chrono::microseconds(1000);
        std::this_thread::sleep_until(next);
    }
}

Counted allocations_over_1000_ticks(DeviceState state, const char* scene_file = "sogetsu_upright_in_suiban.json") {
    ShimDevice shim; // outlives the world, whose device's transport calls it
    std::atomic<bool> first_open{true};
    Counted out;
    {
        auto scene = load_scene(std::string(IKEBANA_ASSET_DIR) + "/scenes/" + scene_file);
        EXPECT_TRUE(scene) << scene.error().message;
        if (!scene) return out;
        auto made = World::create(*scene);
        EXPECT_TRUE(made) << made.error().message;
        if (!made) return out;
        World& w = **made;
        devices::DeviceCapabilities expected{.name = "DIY", .has_force_output = true, .max_force_n = devices::diy_max_force_n,
                                             .workspace_half_extent_m = glm::dvec3{devices::diy_workspace_half_extent_m},
                                             .silent_after_us = devices::diy_silent_after_us};
        // Opened once; gone for good after that (a lost or unplugged device stays away: its steady state).
        w.attach_device(0, std::make_unique<devices::ReconnectingDevice>(
                               [&]() -> Result<std::unique_ptr<devices::HapticDevice>> {
                                   if (!first_open.exchange(false)) return make_error(ErrorCode::device_error, "not plugged in");
                                   return std::unique_ptr<devices::HapticDevice>(std::make_unique<devices::DiyForceDevice>(
                                       devices::make_hidapi_transport(ShimDevice::api(), &shim, "shim")));
                               },
                               expected, 5000));
        sched::DeterministicClock clock(w.schedule);
        run_paced(clock, 400); // attached, engaged, every buffer at its size
        switch (state) {
        case DeviceState::connected: break;
        case DeviceState::silent: shim.sends_diy_reports = false; break;
        case DeviceState::lost: shim.writes_fail = true; break;
        case DeviceState::unplugged: shim.reads_fail = true; break;
        case DeviceState::refusing: shim.corrupt_reports = true; break;
        }
        run_paced(clock, 100); // into that state
        const auto* links = w.sim.resource<const systems::HandLinks>();
        const components::DeviceLink want = state == DeviceState::connected   ? components::DeviceLink::answering
                                            : state == DeviceState::silent    ? components::DeviceLink::silent
                                            : state == DeviceState::lost      ? components::DeviceLink::lost
                                            : state == DeviceState::unplugged ? components::DeviceLink::unplugged
                                                                              : components::DeviceLink::silent;
        out.reached_state = links && links->link[0] == want;
        test::count_allocations_in_lane("sim");
        run_paced(clock, 1000);
        test::count_allocations_in_lane(nullptr);
        out.allocations = test::allocations_counted();
        out.where = test::where_allocations_came_from();
    }
    EXPECT_FALSE(shim.problems());
    return out;
}

} // namespace

// Every device state: a steady tick allocates nothing, and the hand's link says the state was reached
// (a device that sends only reports it refuses is silent: nothing good arrives).
class LaneAllocationInState : public ::testing::TestWithParam<DeviceState> {};

TEST_P(LaneAllocationInState, ASteadyTickAllocatesNothing) {
    const Counted c = allocations_over_1000_ticks(GetParam());
    EXPECT_TRUE(c.reached_state);
    EXPECT_EQ(c.allocations, 0u) << c.where;
}

INSTANTIATE_TEST_SUITE_P(WithTheDevice, LaneAllocationInState,
                         ::testing::Values(DeviceState::connected, DeviceState::silent, DeviceState::lost, DeviceState::unplugged, DeviceState::refusing),
                         [](const ::testing::TestParamInfo<DeviceState>& param) {
                             switch (param.param) {
                             case DeviceState::connected: return std::string("Connected");
                             case DeviceState::silent: return std::string("Silent");
                             case DeviceState::lost: return std::string("Lost");
                             case DeviceState::unplugged: return std::string("Unplugged");
                             case DeviceState::refusing: return std::string("SendingReportsItRefuses");
                             }
                             return std::string("Unknown");
                         });

// The branches with twigs and leaves (two forked willows, two cherries) publish pieces of their own.
TEST(LaneAllocation, ASteadyTickOfTheArrangementWithItsBranchesAllocatesNothing) {
    const Counted c = allocations_over_1000_ticks(DeviceState::connected, "arrangement.json");
    EXPECT_EQ(c.allocations, 0u) << c.where;
}

// The counter itself: an allocation made while the lane runs is seen, one made elsewhere is not.
TEST(LaneAllocation, TheCounterSeesAnAllocationMadeWhileTheLaneRunsAndNoneMadeOutsideIt) {
    ecs::Registry sim_world;
    ecs::Registry main_world;
    sched::Schedule schedule;
    ASSERT_TRUE(schedule.add_lane({"sim", &sim_world, sched::LaneThread::own, {"loop"}}));
    ASSERT_TRUE(schedule.add_lane({"main", &main_world, sched::LaneThread::caller, {"frame"}}));
    std::vector<std::unique_ptr<int>> kept;
    sched::SystemDesc allocating;
    allocating.name = "allocating";
    allocating.lane = "sim";
    allocating.phase = "loop";
    allocating.rate = "haptic";
    allocating.run = [&](sched::SystemContext& ctx) {
        if (ctx.firing % 100 == 0) kept.push_back(std::make_unique<int>(1));
    };
    sched::SystemDesc elsewhere;
    elsewhere.name = "elsewhere";
    elsewhere.lane = "main";
    elsewhere.phase = "frame";
    elsewhere.rate = "render";
    elsewhere.run = [](sched::SystemContext&) { auto p = std::make_unique<double[]>(64); (void)p; };
    ASSERT_TRUE(schedule.add(allocating));
    ASSERT_TRUE(schedule.add(elsewhere));
    ASSERT_TRUE(schedule.finalize());
    sched::DeterministicClock clock(schedule);
    kept.reserve(64);
    test::count_allocations_in_lane("sim");
    clock.run_for_us(1'000'000);
    test::count_allocations_in_lane(nullptr);
    EXPECT_EQ(test::allocations_counted(), 10u);
    EXPECT_NE(test::where_allocations_came_from().find("allocation 1 (10 times):"), std::string::npos);
}

// A whole insertion with a stem, twice: a scripted hand takes the standing sunflower, pulls it out,
// carries it aside and pushes it back in (pins engaged, an insertion recorded, the bottom's wear),
// while the other hand's DIY device is connected. The first time round, scratch buffers take the sizes
// this stem needs; the second time round nothing of it (grabbing and letting go, contact, insertion,
// its record and the pins it met) allocates on the lane.
TEST(LaneAllocation, TakingAStemOutOfThePinsAndPushingItBackInASecondTimeAllocatesNothing) {
    ShimDevice shim;
    std::uint64_t counted = 0;
    std::string where;
    {
        SceneDef scene = test::kenzan_bench();
        scene.flowers.push_back({"sunflower", Placement::inserted, {-0.006, 0.0, 0.010}, glm::normalize(glm::dvec3{0.5, 0.0, 0.866}), 0.013});
        test::add_two_hands(scene, {-0.12, -0.06, 0.15}, {0.12, -0.06, 0.15});
        auto w = test::world_of(scene);
        ASSERT_TRUE(w);
        w->attach_device(0, std::make_unique<devices::DiyForceDevice>(devices::make_hidapi_transport(ShimDevice::api(), &shim, "shim")));
        sched::DeterministicClock clock(w->schedule);
        clock.run_for_us(2'000'000);
        const glm::dvec3 grip = w->sim.get<components::StemPoints>(w->flowers[0].entity).position_m[10];
        const double lift = 0.045;
        const double aside = 0.02;
        // Out and in 2 cm aside, the hand away; then the same again from where it stands then.
        const auto cycle = [&](double t0, glm::dvec3 at) {
            return test::script({{t0, at.x + 0.03, at.y, at.z, 0},                {t0 + 0.5, at.x, at.y, at.z, 0},
                                 {t0 + 0.6, at.x, at.y, at.z, 1},                 {t0 + 1.6, at.x, at.y, at.z + lift, 1},
                                 {t0 + 2.4, at.x, at.y + aside, at.z + lift, 1},  {t0 + 3.6, at.x, at.y + aside, at.z, 1},
                                 {t0 + 3.8, at.x, at.y + aside, at.z, 0},         {t0 + 4.4, at.x + 0.05, at.y + aside, at.z, 0},
                                 {t0 + 9.0, at.x + 0.05, at.y + aside, at.z, 0}});
        };
        w->attach_device(1, cycle(2.0, grip));
        clock.run_for_us(5'000'000); // the first time round: out, aside, in, hand away
        const auto flower = w->flowers[0].entity;
        ASSERT_EQ(w->sim.get<components::InsertionHistory>(flower).insertions, 1u);
        w->attach_device(1, cycle(7.0, w->sim.get<components::StemPoints>(flower).position_m[10]));
        test::count_allocations_in_lane("sim");
        clock.run_for_us(5'000'000); // the second
        test::count_allocations_in_lane(nullptr);
        counted = test::allocations_counted();
        where = test::where_allocations_came_from();
        EXPECT_EQ(w->sim.get<components::InsertionHistory>(flower).insertions, 2u) << "the stem went out and back in again";
        EXPECT_GT(w->sim.get<components::InsertionHistory>(flower).records.back().pins.size(), 0u);
    }
    EXPECT_EQ(counted, 0u) << where;
    EXPECT_FALSE(shim.problems());
}

namespace {

// A branch or flower standing in the kenzan, one hand held still where `at` says; what the lane
// allocates while `act` changes the stem's structure and the next second runs (the loose piece falls,
// is drawn, meets the table).
struct Structural {
    std::uint64_t allocations = 0;
    std::string where;
};

template <typename Act>
void allocations_while(const std::string& species, Act act) {
    SceneDef scene = test::kenzan_bench();
    scene.flowers.push_back({species, Placement::inserted, {0.0, 0.0, 0.0}, glm::normalize(glm::dvec3{0.1, 0.0, 1.0}), 0.013});
    scene.hands.push_back({1, {0.15, -0.15, 0.3}, 0.02, ""});
    auto w = test::world_of(scene);
    if (!w) return;
    sched::DeterministicClock clock(w->schedule);
    clock.run_for_us(500'000);
    act(*w, clock);
}

void count_over(sched::DeterministicClock& clock, std::int64_t us, Structural& out) {
    test::count_allocations_in_lane("sim");
    clock.run_for_us(us);
    test::count_allocations_in_lane(nullptr);
    out.allocations = test::allocations_counted();
    out.where = test::where_allocations_came_from();
}

glm::dvec3 middle_of_first_leaf(World& w, ecs::Entity flower) {
    for (const ecs::Entity child : w.sim.get<const ecs::Children>(flower).entities) {
        const auto* part = w.sim.try_get<const components::Part>(child);
        if (part && part->kind == components::PartKind::leaf) {
            return systems::part_middle(*part, w.sim.get<const components::StemPoints>(flower), w.sim.try_get<const components::StemFrame>(flower));
        }
    }
    ADD_FAILURE() << "no leaf";
    return glm::dvec3{0.0};
}

} // namespace

// A cut (C) changes a stem's structure: its points laid anew, its bends moved, the twigs and leaves on the
// part cut off gone with it. It draws on what the scene reserved when it loaded: nothing allocated on the
// lane, for a forked willow (twigs go) and a chrysanthemum (leaves go).
TEST(LaneAllocation, CuttingAStemsBottomOffAllocatesNothingOnTheLane) {
    for (const std::string species : {"willow_branch", "chrysanthemum"}) {
        std::size_t parts_before = 0;
        std::size_t parts_after = 0;
        allocations_while(species, [&](World& w, sched::DeterministicClock& clock) {
            const auto flower = w.flowers[0].entity;
            const auto owned = [&] {
                const auto* twigs = w.sim.try_get<const components::Twigs>(flower);
                return (twigs ? twigs->entities.size() : 0) + w.sim.get<const ecs::Children>(flower).entities.size();
            };
            parts_before = owned();
            w.sim.emplace_or_replace<components::CutRequest>(flower, components::CutRequest{0.16});
            Structural counted;
            count_over(clock, 1'000'000, counted);
            parts_after = owned();
            EXPECT_EQ(w.sim.get<const components::InsertionHistory>(flower).cuts, 1u) << species << ": the cut was made";
            EXPECT_EQ(counted.allocations, 0u) << species << ":\n" << counted.where;
        });
        EXPECT_LT(parts_after, parts_before) << species << ": what grew on the part cut off went with it";
    }
}

// Pruning (P) at the hand: a twig off at its fork (it keeps its own twigs as a loose branch) or a leaf
// stripped onto a stalk of its own. The pruning itself (the command taken, the piece found, the change
// applied) draws on what the scene reserved; the physics, the frame's update and the published frame,
// which then meet a body they had not met, use working memory sized for the scene's BodyCapacity when
// it loaded. Nothing on the lane allocates, from the press through the piece's fall to the table.
TEST(LaneAllocation, PruningATwigOrStrippingALeafAllocatesNothingOnTheLane) {
    std::size_t loose = 0;
    const auto prune_at = [](World& w, sched::DeterministicClock& clock, glm::dvec3 at, const char* what) {
        w.attach_device(1, test::script({{0.0, at.x, at.y, at.z, 0}, {100.0, at.x, at.y, at.z, 0}}));
        clock.run_for_us(300'000);
        ASSERT_TRUE(w.trainee.push({systems::TraineeCommand::Kind::prune, 1, 0.0}));
        test::count_allocations_in_lane("sim");
        clock.run_for_us(1'000'000); // pruned, and what came off falls to the table
        test::count_allocations_in_lane(nullptr);
        EXPECT_EQ(test::allocations_counted(), 0u) << what << ", pruned and falling:\n" << test::where_allocations_came_from();
        Structural steady;
        count_over(clock, 1'000'000, steady);
        EXPECT_EQ(steady.allocations, 0u) << what << ", lying on the table:\n" << steady.where;
    };
    allocations_while("cherry_branch", [&](World& w, sched::DeterministicClock& clock) {
        const auto flower = w.flowers[0].entity;
        ecs::Entity target = ecs::null_entity;
        for (const ecs::Entity t : w.sim.get<const components::Twigs>(flower).entities) {
            if (w.sim.get<const components::StemFork>(t).parent == flower) target = t;
        }
        ASSERT_FALSE(target.is_null());
        prune_at(w, clock, w.sim.get<const components::StemPoints>(target).position_m[1], "twig");
        EXPECT_TRUE(w.sim.all_of<components::Cutting>(target)) << "the twig was pruned";
    });
    allocations_while("sunflower", [&](World& w, sched::DeterministicClock& clock) {
        prune_at(w, clock, middle_of_first_leaf(w, w.flowers[0].entity), "leaf");
        w.sim.view<const components::Cutting>().each([&](ecs::Entity, const components::Cutting&) { ++loose; });
    });
    EXPECT_EQ(loose, 1u) << "the leaf was stripped onto a stalk of its own";
}
