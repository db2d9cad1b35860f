#include <gtest/gtest.h>

#include <random>

#include "engine/ecs/registry.hpp"
#include "engine/sched/clocks.hpp"

using namespace ikebana;
using namespace ikebana::sched;

namespace {
struct Log {
    std::vector<std::pair<std::int64_t, std::string>> entries;
};

SystemDesc recorder(std::string name, std::string rate, Log& log, std::string phase = "p") {
    SystemDesc d;
    d.name = name;
    d.lane = "sim";
    d.phase = std::move(phase);
    d.rate = std::move(rate);
    d.run = [&log, name](SystemContext& ctx) { log.entries.emplace_back(ctx.time_us, name); };
    return d;
}
} // namespace

TEST(DeterministicClock, EverySystemFiresAtItsOwnRate) {
    ecs::Registry reg;
    Schedule s;
    ASSERT_TRUE(s.add_lane({"sim", &reg, LaneThread::caller, {"p"}}));
    Log log;
    for (const char* rate : {"haptic", "position_estimate", "position_check", "render"}) {
        ASSERT_TRUE(s.add(recorder(rate, rate, log)));
    }
    ASSERT_TRUE(s.finalize());
    DeterministicClock clock(s);
    clock.run_for_us(3'000'000);
    EXPECT_EQ(s.find("haptic")->stats.calls, 3000u);
    EXPECT_EQ(s.find("position_estimate")->stats.calls, 300u);
    EXPECT_EQ(s.find("position_check")->stats.calls, 48u);
    EXPECT_EQ(s.find("render")->stats.calls, 90u);
    // Times never go backwards, and 30 Hz firings are spaced 33333 or 33334 µs: no drift.
    std::int64_t prev_render = -1;
    for (std::size_t i = 1; i < log.entries.size(); ++i) EXPECT_LE(log.entries[i - 1].first, log.entries[i].first);
    for (const auto& [t, name] : log.entries) {
        if (name != "render") continue;
        if (prev_render >= 0) {
            EXPECT_TRUE(t - prev_render == 33333 || t - prev_render == 33334) << t - prev_render;
        }
        prev_render = t;
    }
}

TEST(DeterministicClock, TiesFollowRegistrationOrderWithinPhaseAndPhaseOrder) {
    ecs::Registry reg;
    Schedule s;
    ASSERT_TRUE(s.add_lane({"sim", &reg, LaneThread::caller, {"early", "late"}}));
    Log log;
    ASSERT_TRUE(s.add(recorder("render_late", "render", log, "late")));
    ASSERT_TRUE(s.add(recorder("haptic_early", "haptic", log, "early")));
    ASSERT_TRUE(s.add(recorder("check_early", "position_check", log, "early")));
    ASSERT_TRUE(s.finalize());
    DeterministicClock clock(s);
    clock.run_until(1);
    ASSERT_EQ(log.entries.size(), 3u); // all three are due at t = 0
    EXPECT_EQ(log.entries[0].second, "haptic_early");
    EXPECT_EQ(log.entries[1].second, "check_early");
    EXPECT_EQ(log.entries[2].second, "render_late");
}

TEST(DeterministicClock, DeltaIsTheExactSpacingOfTheTimeline) {
    ecs::Registry reg;
    Schedule s;
    ASSERT_TRUE(s.add_lane({"sim", &reg, LaneThread::caller, {"p"}}));
    double total = 0.0;
    SystemDesc d;
    d.name = "render";
    d.lane = "sim";
    d.phase = "p";
    d.rate = "render";
    d.run = [&](SystemContext& ctx) { total += ctx.dt_s; };
    ASSERT_TRUE(s.add(d));
    ASSERT_TRUE(s.finalize());
    DeterministicClock clock(s);
    clock.run_for_us(10'000'000);
    EXPECT_NEAR(total, 10.0, 1e-9);
}

TEST(DeterministicClock, ChangedRateTakesEffect) {
    ecs::Registry reg;
    Schedule s;
    ASSERT_TRUE(s.rates().set("render", 60.0));
    ASSERT_TRUE(s.add_lane({"sim", &reg, LaneThread::caller, {"p"}}));
    Log log;
    ASSERT_TRUE(s.add(recorder("r", "render", log)));
    ASSERT_TRUE(s.finalize());
    DeterministicClock clock(s);
    clock.run_for_us(1'000'000);
    EXPECT_EQ(s.find("r")->stats.calls, 60u);
}

TEST(DeterministicClock, StructuralChangesLandAfterEachSystem) {
    struct Marker {};
    ecs::Registry reg;
    Schedule s;
    ASSERT_TRUE(s.add_lane({"sim", &reg, LaneThread::caller, {"spawn", "count"}}));
    std::size_t seen_by_counter = 0;
    SystemDesc spawn;
    spawn.name = "spawn";
    spawn.lane = "sim";
    spawn.phase = "spawn";
    spawn.rate = "render";
    spawn.run = [](SystemContext& ctx) {
        const auto e = ctx.registry.commands().create();
        ctx.registry.commands().emplace<Marker>(e);
    };
    SystemDesc counter = spawn;
    counter.name = "count";
    counter.phase = "count";
    counter.run = [&](SystemContext& ctx) { seen_by_counter = ctx.registry.count<Marker>(); };
    ASSERT_TRUE(s.add(spawn));
    ASSERT_TRUE(s.add(counter));
    ASSERT_TRUE(s.finalize());
    DeterministicClock clock(s);
    clock.run_until(1);
    EXPECT_EQ(seen_by_counter, 1u) << "the spawn system's commands were applied before the next system ran";
}

namespace {
struct Body {
    glm::dvec3 position{};
    glm::dvec3 velocity{};
};

// A small world with noise injected from a seeded RNG: the kind of thing determinism must survive.
std::uint64_t run_world(std::uint64_t seed, double seconds) {
    ecs::Registry reg;
    reg.set_resource<std::mt19937_64>(seed);
    for (int i = 0; i < 20; ++i) reg.emplace<Body>(reg.create(), glm::dvec3{i, 0, 0});
    Schedule s;
    EXPECT_TRUE(s.add_lane({"sim", &reg, LaneThread::caller, {"forces", "integrate"}}));
    SystemDesc kick;
    kick.name = "kick";
    kick.lane = "sim";
    kick.phase = "forces";
    kick.rate = "position_check";
    kick.writes = components<Body>();
    kick.run = [](SystemContext& ctx) {
        auto& rng = *ctx.registry.resource<std::mt19937_64>();
        std::uniform_real_distribution<double> u(-1.0, 1.0);
        ctx.registry.view<Body>().each([&](ecs::Entity, Body& b) { b.velocity += glm::dvec3{u(rng), u(rng), u(rng)}; });
    };
    SystemDesc integrate;
    integrate.name = "integrate";
    integrate.lane = "sim";
    integrate.phase = "integrate";
    integrate.rate = "haptic";
    integrate.writes = components<Body>();
    integrate.run = [](SystemContext& ctx) {
        ctx.registry.view<Body>().each([&](ecs::Entity, Body& b) {
            b.velocity *= 0.999;
            b.position += b.velocity * ctx.dt_s;
        });
    };
    EXPECT_TRUE(s.add(kick));
    EXPECT_TRUE(s.add(integrate));
    EXPECT_TRUE(s.finalize());
    DeterministicClock clock(s);
    clock.run_for_us(static_cast<std::int64_t>(seconds * 1e6));
    return reg.state_hash();
}
} // namespace

TEST(DeterministicClock, SameInputsGiveBitIdenticalWorld) {
    EXPECT_EQ(run_world(7, 2.0), run_world(7, 2.0));
}

TEST(DeterministicClock, DifferentInputGivesDifferentWorld) {
    EXPECT_NE(run_world(7, 2.0), run_world(8, 2.0));
}

// A skip is computed, not stepped (a recorded skip may span hours of 1 kHz firings), and lands on the
// first firing due at or after its time, as stepping one firing at a time does, for any rate.
TEST(DeterministicClock, ASkipLandsOnTheFirstFiringDueAtOrAfterItsTimeWithoutSteppingThere) {
    for (const std::int64_t rate_mhz : {1'000'000ll, 30'000ll, 16'000ll, 100'000ll, 333'333ll, 7ll}) {
        for (const std::int64_t t : {1ll, 999ll, 1'000ll, 33'333ll, 33'334ll, 1'234'567ll, 62'500'001ll}) {
            ScheduledSystem stepped;
            stepped.rate_mhz = rate_mhz;
            stepped.next_due_us = stepped.due_us(3);
            stepped.firing = 3;
            ScheduledSystem computed = stepped;
            std::uint64_t count = 0;
            while (stepped.next_due_us < t) {
                ++stepped.firing;
                ++count;
                stepped.next_due_us = stepped.due_us(stepped.firing);
            }
            EXPECT_EQ(computed.skip_until(t), count) << rate_mhz << " mHz to " << t << " us";
            EXPECT_EQ(computed.firing, stepped.firing) << rate_mhz << " mHz to " << t << " us";
            EXPECT_EQ(computed.next_due_us, stepped.next_due_us);
        }
    }
    ScheduledSystem day;
    day.rate_mhz = 1'000'000;
    EXPECT_EQ(day.skip_until(86'400'000'000), 86'400'000u) << "a day of 1 kHz firings, at once";
    EXPECT_EQ(day.next_due_us, 86'400'000'000);
}
