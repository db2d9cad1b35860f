#include <gtest/gtest.h>

#include <atomic>
#include <stdexcept>
#include <chrono>
#include <thread>

#include "engine/devices/hid_devices.hpp"
#include "engine/devices/safe_force_device.hpp"
#include "engine/ecs/registry.hpp"
#include "engine/sched/clocks.hpp"
#include "engine/sched/triple_buffer.hpp"
#include "tests/support/hidapi_shim.hpp"

using namespace ikebana;
using namespace ikebana::sched;

namespace {
struct Sample {
    std::uint64_t tick = 0;
    double force = 0.0;
};

// Two worlds, one channel: the haptic lane publishes, the main lane reads, as the app does.
struct TwoLanes {
    ecs::Registry haptic_world;
    ecs::Registry main_world;
    TripleBuffer<Sample> channel;
    std::uint64_t haptic_ticks = 0; // touched by the haptic thread only
    std::uint64_t newest_seen = 0;  // touched by the main thread only
    std::uint64_t out_of_order = 0;
    Schedule schedule;

    explicit TwoLanes(std::chrono::milliseconds main_stall) {
        EXPECT_TRUE(schedule.add_lane({"haptic", &haptic_world, LaneThread::own, {"loop"}}));
        EXPECT_TRUE(schedule.add_lane({"main", &main_world, LaneThread::caller, {"frame"}}));
        SystemDesc force;
        force.name = "force_output";
        force.lane = "haptic";
        force.phase = "loop";
        force.rate = "haptic";
        force.run = [this](SystemContext& ctx) {
            ++haptic_ticks;
            channel.write_buffer() = Sample{ctx.firing + 1, static_cast<double>(ctx.firing)};
            channel.publish();
        };
        SystemDesc frame;
        frame.name = "frame";
        frame.lane = "main";
        frame.phase = "frame";
        frame.rate = "render";
        frame.run = [this, main_stall](SystemContext&) {
            channel.update();
            const auto tick = channel.read_buffer().tick;
            if (tick < newest_seen) ++out_of_order;
            newest_seen = tick;
            if (main_stall.count() > 0) std::this_thread::sleep_for(main_stall);
        };
        EXPECT_TRUE(schedule.add(force));
        EXPECT_TRUE(schedule.add(frame));
        EXPECT_TRUE(schedule.finalize());
    }
};
} // namespace

TEST(RealtimeClock, HapticLaneRunsAtItsRateOnItsOwnThread) {
    TwoLanes world(std::chrono::milliseconds(0));
    RealtimeClock clock(world.schedule);
    const auto start = std::chrono::steady_clock::now();
    const auto reports = clock.run_for(0.5);
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_GE(elapsed, 0.45);
    // Generous bounds: sanitizers and a loaded CI machine slow things down, and skipped firings count.
    const auto* h = world.schedule.find("force_output");
    EXPECT_GE(h->stats.calls + h->stats.skipped_firings, 450u);
    EXPECT_LE(h->stats.calls, 501u);
    EXPECT_EQ(world.out_of_order, 0u) << "snapshots never go back in time";
    EXPECT_GT(world.newest_seen, 0u) << "the main lane saw the haptic lane's snapshots";
    EXPECT_EQ(reports.size(), 2u);
}

TEST(RealtimeClock, StalledFrameDoesNotStallHapticLoop) {
    // Every frame stalls for 80 ms, so the main lane falls far behind its 30 Hz.
    TwoLanes world(std::chrono::milliseconds(80));
    RealtimeClock clock(world.schedule);
    (void)clock.run_for(0.6);
    const auto* h = world.schedule.find("force_output");
    const auto* frame = world.schedule.find("frame");
    EXPECT_LE(frame->stats.calls, 10u) << "the frames really stalled";
    EXPECT_GE(h->stats.calls + h->stats.skipped_firings, 500u) << "the haptic loop kept its pace meanwhile";
    EXPECT_GE(h->stats.calls, 300u);
}

TEST(RealtimeClock, CatchUpIsClampedAndCounted) {
    ecs::Registry reg;
    Schedule s;
    ASSERT_TRUE(s.add_lane({"main", &reg, LaneThread::caller, {"p"}}));
    int calls = 0;
    SystemDesc slow;
    slow.name = "slow";
    slow.lane = "main";
    slow.phase = "p";
    slow.rate = "haptic";
    slow.run = [&](SystemContext&) {
        if (++calls == 1) std::this_thread::sleep_for(std::chrono::milliseconds(200));
    };
    ASSERT_TRUE(s.add(slow));
    ASSERT_TRUE(s.finalize());
    RealtimeClock clock(s, RealtimeConfig{.max_catchup_us = 20'000, .on_skip = {}});
    const auto reports = clock.run_for(0.4);
    EXPECT_GE(reports[0].clamp_events, 1u);
    // 200 ms behind with a 20 ms window: at least 150 firings dropped instead of run in a burst.
    EXPECT_GE(s.find("slow")->stats.skipped_firings, 150u);
    EXPECT_GE(s.find("slow")->stats.missed_deadlines, 1u);
}

TEST(RealtimeClock, ExternalStopEndsTheRun) {
    ecs::Registry reg;
    Schedule s;
    ASSERT_TRUE(s.add_lane({"main", &reg, LaneThread::caller, {"p"}}));
    std::atomic<bool> stop{false};
    SystemDesc closer;
    closer.name = "window";
    closer.lane = "main";
    closer.phase = "p";
    closer.rate = "render";
    closer.run = [&](SystemContext& ctx) {
        if (ctx.firing == 3) stop = true;
    };
    ASSERT_TRUE(s.add(closer));
    ASSERT_TRUE(s.finalize());
    RealtimeClock clock(s);
    const auto start = std::chrono::steady_clock::now();
    (void)clock.run_for(10.0, &stop);
    EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(2));
    EXPECT_EQ(s.find("window")->stats.calls, 4u);
}

TEST(TripleBuffer, ReaderGetsNewestCompleteSnapshotAcrossThreads) {
    struct Big {
        std::array<std::uint64_t, 64> words{};
    };
    TripleBuffer<Big> buffer;
    std::atomic<bool> done{false};
    std::thread writer([&] {
        for (std::uint64_t i = 1; i <= 200'000; ++i) {
            buffer.write_buffer().words.fill(i);
            buffer.publish();
        }
        done = true;
    });
    std::uint64_t last = 0;
    std::uint64_t torn = 0;
    std::uint64_t backwards = 0;
    while (!done.load()) {
        if (!buffer.update()) continue;
        const auto& snapshot = buffer.read_buffer();
        const auto first = snapshot.words[0];
        for (auto w : snapshot.words) torn += (w != first);
        backwards += first < last;
        last = first;
    }
    writer.join();
    buffer.update();
    EXPECT_EQ(torn, 0u);
    EXPECT_EQ(backwards, 0u);
    EXPECT_EQ(buffer.read_buffer().words[0], 200'000u);
}

// Asking for real-time priority changes nothing the lanes do; the report says whether it was granted
// (only an own-thread lane can be, and only when asked).
TEST(RealtimeClock, FifoPriorityIsAskedOnlyForOwnThreadLanes) {
    TwoLanes asked(std::chrono::milliseconds(0));
    RealtimeClock with_fifo(asked.schedule, RealtimeConfig{.max_catchup_us = 50'000, .own_thread_timer_slack_ns = 1'000, .own_thread_fifo_priority = 10, .on_skip = {}});
    const auto reports = with_fifo.run_for(0.2);
    ASSERT_EQ(reports.size(), 2u);
    EXPECT_FALSE(reports[1].fifo_priority) << "the caller's lane keeps the caller's priority";
    EXPECT_GT(reports[0].firings, 100u);
    EXPECT_EQ(asked.out_of_order, 0u);

    TwoLanes not_asked(std::chrono::milliseconds(0));
    RealtimeClock plain(not_asked.schedule);
    const auto plain_reports = plain.run_for(0.05);
    EXPECT_FALSE(plain_reports[0].fifo_priority);
}

// What the clamp dropped, told as it happened, lets the deterministic clock drop the same firings:
// a recording of a real-time session replays on the same ticks.
TEST(RealtimeClock, TheFiringsTheClampDroppedAreToldAndTheDeterministicClockDropsTheSame) {
    struct Run {
        ecs::Registry reg;
        Schedule s;
        std::vector<std::int64_t> times;
        explicit Run(bool stall) {
            EXPECT_TRUE(s.add_lane({"main", &reg, LaneThread::caller, {"p"}}));
            SystemDesc slow;
            slow.name = "slow";
            slow.lane = "main";
            slow.phase = "p";
            slow.rate = "haptic";
            slow.run = [this, stall](SystemContext& ctx) {
                times.push_back(ctx.time_us);
                if (stall && times.size() == 20) std::this_thread::sleep_for(std::chrono::milliseconds(120));
            };
            EXPECT_TRUE(s.add(slow));
            EXPECT_TRUE(s.finalize());
        }
    };
    Run live(true);
    struct Skip {
        std::size_t lane;
        std::int64_t due_us, until_us;
    };
    std::vector<Skip> skips;
    RealtimeClock clock(live.s, RealtimeConfig{.max_catchup_us = 20'000, .on_skip = [&](std::size_t lane, std::int64_t due, std::int64_t until) {
                                                   skips.push_back({lane, due, until});
                                               }});
    (void)clock.run_for(0.3);
    ASSERT_GE(skips.size(), 1u);
    ASSERT_GE(live.times.size(), 2u);
    EXPECT_GT(skips[0].until_us, skips[0].due_us + 50'000) << "120 ms behind with a 20 ms window drops about 100 ms of firings";

    Run replay(false);
    DeterministicClock det(replay.s);
    for (const auto& k : skips) {
        det.run_until(k.due_us);
        det.skip_lane(k.lane, k.until_us);
    }
    det.run_until(live.times.back() + 1);
    EXPECT_EQ(replay.times, live.times);
}

// A lane that throws (an undeclared access, a logic error in release builds) used to end in
// std::terminate with the force still on. Now the clock zeroes every pushing device at once, stops
// every lane and says which lane threw and why.
TEST(RealtimeClock, ALaneThatThrowsStopsTheRunAndEveryPushingDeviceIsSentZeroAtOnce) {
    ikebana::test::ShimDevice shim;
    auto chain = devices::make_force_safe(std::make_unique<devices::DiyForceDevice>(
        devices::make_hidapi_transport(ikebana::test::ShimDevice::api(), &shim, "shim", devices::HidTransportOptions{.fifo_priority = 0, .close_wait = std::chrono::milliseconds(200), .say = {}})));
    ecs::Registry haptic_world;
    ecs::Registry main_world;
    Schedule schedule;
    ASSERT_TRUE(schedule.add_lane({"haptic", &haptic_world, LaneThread::own, {"loop"}}));
    ASSERT_TRUE(schedule.add_lane({"main", &main_world, LaneThread::caller, {"frame"}}));
    std::atomic<double> pushed_n{0.0};
    SystemDesc push;
    push.name = "push";
    push.lane = "haptic";
    push.phase = "loop";
    push.rate = "haptic";
    push.run = [&](SystemContext& ctx) {
        // Once it pushes (the ramp runs on the wall clock and starts again after a stall: a loaded
        // machine takes longer than 400 ticks), or at the latest after 8 s.
        if ((ctx.firing >= 400 && pushed_n.load() > 0.5) || ctx.firing >= 8'000) throw std::logic_error("push: an undeclared access");
        (void)chain->poll(ctx.time_us);
        (void)chain->send_force({0.0, 0.0, 1.5});
        pushed_n = std::max(pushed_n.load(), glm::length(chain->last_sent().queued_n));
    };
    SystemDesc frame;
    frame.name = "frame";
    frame.lane = "main";
    frame.phase = "frame";
    frame.rate = "render";
    frame.run = [](SystemContext&) {};
    ASSERT_TRUE(schedule.add(push));
    ASSERT_TRUE(schedule.add(frame));
    ASSERT_TRUE(schedule.finalize());
    RealtimeClock clock(schedule);
    const auto start = std::chrono::steady_clock::now();
    const auto reports = clock.run_for(20.0);
    EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(10)) << "the other lanes stop too";
    ASSERT_EQ(reports.size(), 2u);
    EXPECT_EQ(reports[0].failure, "push: an undeclared access");
    EXPECT_GE(reports[0].zeroed_devices, 1u);
    EXPECT_TRUE(reports[1].failure.empty());
    EXPECT_GT(pushed_n.load(), 0.5) << "it was pushing when the lane threw";
    glm::dvec3 last{1.0};
    ASSERT_TRUE(shim.last_force(last));
    EXPECT_EQ(last, glm::dvec3(0.0)) << "the zero reached the wire before run_for returned";
    EXPECT_FALSE(shim.problems());
}
