#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <mutex>
#include <thread>
#include <vector>

#include "engine/devices/reconnecting_device.hpp"
#include "engine/devices/safe_force_device.hpp"
#include "engine/ecs/registry.hpp"
#include "engine/sched/clocks.hpp"

using namespace ikebana;
using namespace ikebana::devices;

namespace {

// What reached the "motors", with the wall-clock time it got there.
struct Wire {
    struct Entry {
        std::int64_t wall_us;
        glm::dvec3 force_n;
        bool zero; // from zero_force (the watchdog)
    };
    std::mutex mutex;
    std::vector<Entry> entries;
    void push(glm::dvec3 f, bool zero) {
        const std::lock_guard lock(mutex);
        entries.push_back({monotonic_us(), f, zero});
    }
};

struct WireDevice final : HapticDevice {
    Wire& wire;
    DeviceCapabilities caps{"wire", true, 5.0, glm::dvec3{0.1}, true};
    explicit WireDevice(Wire& w) : wire(w) {}
    const DeviceCapabilities& capabilities() const override { return caps; }
    bool unplugged = false;
    Result<DeviceSample> poll(std::int64_t now_us) override {
        if (unplugged) return make_error(ErrorCode::device_error, "read failed");
        DeviceSample s;
        s.time_us = now_us;
        return s;
    }
    Result<void> send_force(glm::dvec3 f) override {
        wire.push(f, false);
        return {};
    }
    Result<void> zero_force() override {
        wire.push(glm::dvec3{0.0}, true);
        return {};
    }
};

ForceSafetyConfig quick_ramp() {
    ForceSafetyConfig c;
    c.max_force_n = 3.0;
    c.max_rate_n_per_s = 300.0;
    c.ramp_up_s = 0.1;
    c.watchdog_us = 2000;
    return c;
}

} // namespace

// The defect this layer exists for: after a real stall shorter than the scheduler's catch-up window,
// the firings that catch up are 1 ms apart on the timeline, so a timeline-based ramp never restarts.
// Here a 1 kHz loop on the real-time clock stalls for 25 ms of wall time while pushing 1 to 2 N; the
// watchdog zeroes the device; the forces sent afterwards must rise from zero within the ramp.
TEST(ForceSafety, RampsFromZeroAfterAWallClockStall) {
    Wire wire;
    SafeForceDevice device(std::make_unique<WireDevice>(wire), quick_ramp());
    ForceWatchdog watchdog([&device] { (void)device.zero_force(); }, 2000);

    ecs::Registry world;
    sched::Schedule schedule;
    ASSERT_TRUE(schedule.add_lane({"haptic", &world, sched::LaneThread::own, {"loop"}}));
    std::atomic<std::int64_t> stall_end_us{0};
    sched::SystemDesc loop;
    loop.name = "force_output";
    loop.lane = "haptic";
    loop.phase = "loop";
    loop.rate = "haptic";
    loop.run = [&](sched::SystemContext&) {
        // Once at least 1 N is being sent (on a loaded machine, a sanitizer build with other tests beside
        // it, small stalls restart the ramp first; half of it needs only 50 clean milliseconds).
        if (stall_end_us.load() == 0 && glm::length(device.last_output()) > 0.999) {
            std::this_thread::sleep_for(std::chrono::milliseconds(25));
            stall_end_us.store(monotonic_us());
        }
        (void)device.send_force({0.0, 0.0, 2.0});
        watchdog.feed();
    };
    ASSERT_TRUE(schedule.add(loop));
    ASSERT_TRUE(schedule.finalize());
    sched::RealtimeClock clock(schedule);
    clock.run_for(2.0);

    const std::lock_guard lock(wire.mutex);
    const std::int64_t resumed = stall_end_us.load();
    ASSERT_GT(resumed, 0) << "the stall happened";
    std::size_t first_after = wire.entries.size();
    bool zeroed_in_stall = false;
    double before_stall_n = 0.0;
    for (std::size_t i = 0; i < wire.entries.size(); ++i) {
        const auto& e = wire.entries[i];
        if (e.wall_us < resumed) {
            if (e.zero) zeroed_in_stall = true;
            else before_stall_n = glm::length(e.force_n);
        } else if (!e.zero && first_after == wire.entries.size()) {
            first_after = i;
        }
    }
    EXPECT_GT(before_stall_n, 0.99) << "the loop pushed 1 N or more before it stalled";
    EXPECT_TRUE(zeroed_in_stall) << "the watchdog zeroed the device during the stall";
    ASSERT_LT(first_after, wire.entries.size()) << "the loop sent forces after the stall";
    // After: never above the ramp's envelope (3 N over 0.1 s from the resume) plus one rate step, and no
    // rise larger than the rate limit allows for the wall time between two sends. Drops are allowed: on
    // a loaded machine the loop may stall again, and a stall or a watchdog zero restarts from zero.
    const auto& config = quick_ramp();
    EXPECT_LT(glm::length(wire.entries[first_after].force_n), 0.31) << "the first force after the stall starts near zero, not where it was";
    double previous = glm::length(wire.entries[first_after].force_n);
    std::int64_t previous_us = wire.entries[first_after].wall_us;
    double largest_after = previous;
    for (std::size_t i = first_after + 1; i < wire.entries.size(); ++i) {
        const auto& e = wire.entries[i];
        const double now = glm::length(e.force_n);
        if (!e.zero) {
            const double since_s = static_cast<double>(e.wall_us - resumed) * 1e-6;
            EXPECT_LE(now, config.max_force_n * since_s / config.ramp_up_s + 0.3 + 1e-9) << "send " << i;
            const double allowed = config.max_rate_n_per_s * static_cast<double>(e.wall_us - previous_us + 1000) * 1e-6;
            EXPECT_LE(now - previous, allowed + 1e-9) << "send " << i << " jumps up";
            largest_after = std::max(largest_after, now);
        }
        previous = now;
        previous_us = e.wall_us;
    }
    EXPECT_GT(largest_after, 0.05) << "the force comes back after the stall, ramping";
}

TEST(ForceSafety, AZeroFromTheWatchdogRestartsTheRampEvenWithoutAStall) {
    Wire wire;
    std::int64_t now = 0;
    SafeForceDevice device(std::make_unique<WireDevice>(wire), quick_ramp(), [&now] { return now; });
    for (int i = 0; i < 200; ++i) {
        now += 1000;
        ASSERT_TRUE(device.send_force({2.0, 0.0, 0.0}));
    }
    EXPECT_NEAR(device.last_output().x, 2.0, 1e-9);
    ASSERT_TRUE(device.zero_force());
    now += 1000; // only 1 ms later: no stall the safety could see by itself
    ASSERT_TRUE(device.send_force({2.0, 0.0, 0.0}));
    EXPECT_EQ(wire.entries.back().force_n, glm::dvec3(0.0)) << "restarts at zero, not at 2 N";
    EXPECT_EQ(device.zeroed(), 1u);
}

TEST(ForceSafety, TheLowerOfOurLimitAndTheDevicesOwnHolds) {
    Wire wire;
    auto inner = std::make_unique<WireDevice>(wire);
    inner->caps.max_force_n = 1.5;
    std::int64_t now = 0;
    SafeForceDevice device(std::move(inner), quick_ramp(), [&now] { return now; });
    for (int i = 0; i < 500; ++i) {
        now += 1000;
        ASSERT_TRUE(device.send_force({0.0, 100.0, 0.0}));
        ASSERT_LE(glm::length(wire.entries.back().force_n), 1.5 + 1e-12);
    }
    EXPECT_NEAR(glm::length(wire.entries.back().force_n), 1.5, 1e-9);
}

TEST(ForceSafety, AnUnpluggedDeviceComesBackRampingFromZero) {
    Wire wire;
    auto inner = std::make_unique<WireDevice>(wire);
    auto* raw = inner.get();
    std::int64_t now = 0;
    SafeForceDevice device(std::move(inner), quick_ramp(), [&now] { return now; });
    for (int i = 0; i < 200; ++i) {
        now += 1000;
        ASSERT_TRUE(device.poll(now));
        ASSERT_TRUE(device.send_force({2.0, 0.0, 0.0}));
    }
    EXPECT_NEAR(device.last_output().x, 2.0, 1e-9);
    raw->unplugged = true;
    now += 1000;
    EXPECT_FALSE(device.poll(now)) << "the failed read is passed on";
    raw->unplugged = false;
    now += 1000;
    ASSERT_TRUE(device.poll(now));
    ASSERT_TRUE(device.send_force({2.0, 0.0, 0.0}));
    EXPECT_EQ(wire.entries.back().force_n, glm::dvec3(0.0)) << "back from an unplug, the force starts from zero";
}

// The watchdog's zero and the 1 kHz sender race on two threads; under ThreadSanitizer this must be
// clean, and no zero may be overtaken by a stale force on the wire.
TEST(ForceSafety, WatchdogAndSenderMayRace) {
    Wire wire;
    SafeForceDevice device(std::make_unique<WireDevice>(wire), quick_ramp());
    std::atomic<bool> done{false};
    std::thread watchdog([&] {
        while (!done.load()) {
            (void)device.zero_force();
            std::this_thread::yield();
        }
    });
    // Until the watchdog has zeroed a few hundred times (on a loaded machine its thread may start late).
    const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(20);
    for (int i = 0; i < 5000 || (device.zeroed() < 200 && std::chrono::steady_clock::now() < give_up); ++i) {
        ASSERT_TRUE(device.send_force({0.0, 0.0, 2.0}));
    }
    done.store(true);
    watchdog.join();
    EXPECT_GT(device.zeroed(), 0u); // before the wire's lock: the device's lock is always taken first
    const std::lock_guard lock(wire.mutex);
    // After each zero on the wire, the next force is at most one rate step above zero.
    for (std::size_t i = 1; i < wire.entries.size(); ++i) {
        if (wire.entries[i - 1].zero && !wire.entries[i].zero) {
            EXPECT_LE(glm::length(wire.entries[i].force_n), 0.3 + 1e-9) << "entry " << i;
        }
    }
}

TEST(ForceSafety, ReconnectingDeviceSendsAndZeroesUnderOneLock) {
    Wire wire;
    ReconnectingDevice device([&]() -> Result<std::unique_ptr<HapticDevice>> { return std::unique_ptr<HapticDevice>(std::make_unique<WireDevice>(wire)); },
                              DeviceCapabilities{"wire", true, 5.0, glm::dvec3{0.1}, true}, 0);
    ASSERT_TRUE(device.poll(0));
    std::atomic<bool> done{false};
    std::thread watchdog([&] {
        while (!done.load()) (void)device.zero_force();
    });
    for (int i = 0; i < 3000; ++i) {
        (void)device.poll(i);
        (void)device.send_force({0.0, 0.0, 1.0});
    }
    done.store(true);
    watchdog.join();
    const std::lock_guard lock(wire.mutex);
    EXPECT_GE(wire.entries.size(), 3000u);
}
