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
    c.wait_for_small_force = false; // the wait has tests of its own (force_safety_test.cpp)
    return c;
}

} // namespace

// The defect this layer exists for: after a real stall shorter than the scheduler's catch-up window,
// the firings that catch up are 1 ms apart on the timeline, so a timeline-based chain never sees it.
// Here a 1 kHz loop on the real-time clock stalls for 25 ms of wall time while pushing 1 to 2 N; the
// watchdog zeroes the device; the forces sent afterwards rise from zero at the rate limit (never a jump
// back to where they were), within the ramp's level, and come back.
TEST(ForceSafety, AfterAWallClockStallTheForceRisesFromZeroAtTheRateLimit) {
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
        // it, small stalls cost the ramp some of its level first).
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
    // After: the first force is one rate step (of at most a watchdog period) above zero, and no rise is
    // larger than the rate limit allows for the wall time between two sends. Drops are allowed: on a
    // loaded machine the loop may stall again, and a watchdog zero brings the output to zero.
    const auto& config = quick_ramp();
    EXPECT_LE(glm::length(wire.entries[first_after].force_n), config.max_rate_n_per_s * 0.002 + 1e-9)
        << "the first force after the stall starts near zero, not where it was";
    double previous = glm::length(wire.entries[first_after].force_n);
    double largest_after = previous;
    for (std::size_t i = first_after + 1; i < wire.entries.size(); ++i) {
        const auto& e = wire.entries[i];
        const double now = glm::length(e.force_n);
        if (!e.zero) {
            // One step covers the wall time since the last, a watchdog period at most (the wire's own
            // timestamps are taken a moment after the chain's clock, so they cannot bound it closer).
            EXPECT_LE(now - previous, config.max_rate_n_per_s * static_cast<double>(config.watchdog_us) * 1e-6 + 1e-9) << "send " << i << " jumps up";
            largest_after = std::max(largest_after, now);
        }
        previous = now;
    }
    EXPECT_GT(largest_after, 1.0) << "the force comes back after the stall";
}

TEST(ForceSafety, AZeroFromTheWatchdogIsNeverFollowedByAJumpBack) {
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
    EXPECT_NEAR(wire.entries.back().force_n.x, 0.3, 1e-9) << "one rate step above zero, not back at 2 N";
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
    // After each zero on the wire, the next force is at most one rate step above zero (a step covers the
    // wall time since the last send, a watchdog period at most: 0.6 N).
    for (std::size_t i = 1; i < wire.entries.size(); ++i) {
        if (wire.entries[i - 1].zero && !wire.entries[i].zero) {
            EXPECT_LE(glm::length(wire.entries[i].force_n), 0.6 + 1e-9) << "entry " << i;
        }
    }
}

TEST(ForceSafety, ReconnectingDeviceSendsAndZeroesUnderOneLock) {
    Wire wire;
    ReconnectingDevice device([&]() -> Result<std::unique_ptr<HapticDevice>> { return std::unique_ptr<HapticDevice>(std::make_unique<WireDevice>(wire)); },
                              DeviceCapabilities{"wire", true, 5.0, glm::dvec3{0.1}, true}, 0);
    // The opener runs on the device's own thread: the device is there within moments.
    const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (!device.poll(0) && std::chrono::steady_clock::now() < give_up) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    ASSERT_TRUE(device.attached());
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

namespace {
// A device that reports while `reporting` (its samples carry the time of their newest report) and
// whose writes fail while `refusing`.
struct ReportingDevice final : HapticDevice {
    Wire& wire;
    DeviceCapabilities caps{"reporting", true, 3.0, glm::dvec3{0.1}, true};
    bool reporting = true;
    const std::atomic<bool>* refusing = nullptr; // set: its writes fail while it is true
    std::int64_t report_us = 0;
    explicit ReportingDevice(Wire& w) : wire(w) { caps.silent_after_us = 20'000; }
    const DeviceCapabilities& capabilities() const override { return caps; }
    Result<DeviceSample> poll(std::int64_t now_us) override {
        if (reporting) report_us = now_us;
        DeviceSample s;
        s.time_us = now_us;
        s.report_us = report_us;
        return s;
    }
    Result<void> send_force(glm::dvec3 f) override {
        if (refusing && refusing->load()) return make_error(ErrorCode::device_error, "write failed");
        wire.push(f, false);
        return {};
    }
    Result<void> zero_force() override {
        wire.push(glm::dvec3{0.0}, true);
        return {};
    }
};
} // namespace

// A device that stays plugged in but stops reporting (a firmware hang): its poll used to hand back the
// last report stamped with the current time, and the host kept pushing against a frozen position. Now
// after 20 ms without a report the hand lets go, the force fades to zero at the rate limit, and when
// reports resume it comes back through the wait for a small force and the ramp.
TEST(ForceSafety, ASilentDeviceLetsGoFadesOutAndComesBackThroughTheWaitAndTheRamp) {
    Wire wire;
    auto inner = std::make_unique<ReportingDevice>(wire);
    auto* raw = inner.get();
    std::int64_t now = 0;
    auto config = quick_ramp();
    config.wait_for_small_force = true;
    SafeForceDevice device(std::move(inner), config, [&now] { return now; });
    const auto tick = [&](glm::dvec3 asked) {
        now += 1000;
        const auto polled = device.poll(now);
        (void)device.send_force(asked);
        return polled;
    };
    for (int i = 0; i < 60; ++i) ASSERT_TRUE(tick({0.0, 0.0, 0.1}));
    for (int i = 0; i < 300; ++i) ASSERT_TRUE(tick({0.0, 0.0, 2.0}));
    ASSERT_NEAR(device.last_output().z, 2.0, 1e-9);
    raw->reporting = false; // hung
    int ticks_until_silent = 0;
    Result<DeviceSample> polled = tick({0.0, 0.0, 2.0});
    while (polled && ticks_until_silent < 100) {
        ++ticks_until_silent;
        polled = tick({0.0, 0.0, 2.0});
    }
    ASSERT_FALSE(polled);
    EXPECT_EQ(polled.error().code, ErrorCode::device_silent);
    EXPECT_EQ(polled.error().text(), "the device has sent nothing for longer than its profile allows");
    EXPECT_EQ(device.silent_for_us(), 21'000) << "how long, for the log";
    EXPECT_EQ(ticks_until_silent, 20) << "silent once 20 ms have passed without a report";
    EXPECT_TRUE(device.silent());
    EXPECT_EQ(device.last_sent().held, ForceHeld::fading);
    double previous = glm::length(device.last_output());
    for (int i = 0; i < 20; ++i) {
        EXPECT_FALSE(tick({0.0, 0.0, 2.0}));
        const double out = glm::length(device.last_output());
        EXPECT_LE(previous - out, 0.3 + 1e-9) << "fades at the rate limit, does not drop";
        EXPECT_LE(out, previous);
        previous = out;
    }
    EXPECT_EQ(device.last_output(), glm::dvec3(0.0)) << "faded to zero within 20 ms";
    raw->reporting = true; // back
    for (int i = 0; i < 100; ++i) ASSERT_TRUE(tick({0.0, 0.0, 2.0}));
    EXPECT_FALSE(device.silent());
    EXPECT_EQ(device.last_output(), glm::dvec3(0.0)) << "back, but 2 N asked: it waits for a small force";
    for (int i = 0; i < 60; ++i) ASSERT_TRUE(tick({0.0, 0.0, 0.5}));
    EXPECT_GT(device.last_output().z, 0.0) << "engaged after 50 ms of a small force";
    EXPECT_LT(device.last_output().z, 0.5) << "and ramping";
}

// Writes that fail were dropped ((void)send_force). Now three in a row and the device is lost: it is
// zeroed as far as it still listens, dropped and opened again off the haptic thread; poll says why
// until the reopened device answers, and the reopened one starts from zero.
TEST(ForceSafety, WritesThatKeepFailingLoseTheDeviceUntilItIsReopened) {
    Wire wire;
    std::atomic<int> opens{0};
    std::atomic<bool> refusing{false};
    auto reconnecting = std::make_unique<ReconnectingDevice>(
        [&]() -> Result<std::unique_ptr<HapticDevice>> {
            ++opens;
            auto d = std::make_unique<ReportingDevice>(wire);
            d->caps.silent_after_us = 0;
            d->refusing = &refusing;
            return std::unique_ptr<HapticDevice>(std::move(d));
        },
        DeviceCapabilities{"reporting", true, 3.0, glm::dvec3{0.1}, true}, 1000);
    auto* raw = reconnecting.get();
    std::int64_t now = 0;
    SafeForceDevice device(std::move(reconnecting), quick_ramp(), [&now] { return now; });
    const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (!device.poll(now += 1000) && std::chrono::steady_clock::now() < give_up) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    ASSERT_TRUE(raw->attached());
    for (int i = 0; i < 200; ++i) {
        ASSERT_TRUE(device.poll(now += 1000));
        ASSERT_TRUE(device.send_force({1.0, 0.0, 0.0}));
    }
    refusing.store(true); // the device stops taking forces
    for (int i = 0; i < SafeForceDevice::lost_after_failures; ++i) {
        EXPECT_FALSE(device.lost());
        ASSERT_TRUE(device.poll(now += 1000));
        EXPECT_FALSE(device.send_force({1.0, 0.0, 0.0})) << "the failure is passed on, and counted";
    }
    EXPECT_TRUE(device.lost());
    EXPECT_EQ(device.write_failures(), 3u);
    EXPECT_FALSE(raw->attached()) << "dropped, to be opened again";
    refusing.store(false); // the reopened device will take forces again
    Result<DeviceSample> back = device.poll(now += 1000);
    if (!back) { // unless the opener thread was quicker than this poll
        EXPECT_EQ(back.error().code, ErrorCode::device_lost);
        EXPECT_EQ(back.error().text(), "the device stopped taking forces; reconnecting");
    }
    while (!back && std::chrono::steady_clock::now() < give_up) {
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
        back = device.poll(now += 1000);
    }
    ASSERT_TRUE(back) << "reopened";
    EXPECT_FALSE(device.lost());
    EXPECT_EQ(opens.load(), 2);
    EXPECT_EQ(raw->reconnects(), 1u);
    ASSERT_TRUE(device.send_force({1.0, 0.0, 0.0}));
    const std::lock_guard lock(wire.mutex);
    EXPECT_EQ(wire.entries.back().force_n, glm::dvec3(0.0)) << "the reopened device starts from zero";
}

// The chain's status says what really left it, and why it differs from the request.
TEST(ForceSafety, TheSentForceAndWhyItDiffersAreReported) {
    Wire wire;
    std::int64_t now = 0;
    auto config = quick_ramp();
    config.wait_for_small_force = true;
    SafeForceDevice device(std::make_unique<WireDevice>(wire), config, [&now] { return now; });
    for (int i = 0; i < 100; ++i) {
        now += 1000;
        ASSERT_TRUE(device.send_force({0.0, 0.0, 24.0}));
    }
    EXPECT_TRUE(device.last_sent().pushes);
    EXPECT_EQ(device.last_sent().sent_n, glm::dvec3(0.0));
    EXPECT_EQ(device.last_sent().held, ForceHeld::waiting);
    for (int i = 0; i < 60; ++i) {
        now += 1000;
        ASSERT_TRUE(device.send_force({0.0, 0.0, 0.1}));
    }
    for (int i = 0; i < 500; ++i) {
        now += 1000;
        ASSERT_TRUE(device.send_force({0.0, 0.0, 24.0}));
    }
    EXPECT_NEAR(device.last_sent().sent_n.z, 3.0, 1e-9);
    EXPECT_EQ(device.last_sent().max_force_n, 3.0);
    EXPECT_EQ(device.last_sent().held, ForceHeld::at_limit);
}
