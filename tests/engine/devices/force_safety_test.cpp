#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <thread>

#include "engine/devices/force_safety.hpp"

using namespace ikebana::devices;

namespace {
ForceSafetyConfig config() {
    ForceSafetyConfig c;
    c.max_force_n = 3.0;
    c.max_rate_n_per_s = 300.0;
    c.ramp_up_s = 0.5;
    c.watchdog_us = 2000;
    return c;
}
// Runs `ticks` 1 kHz ticks requesting `f`; returns the last output.
glm::dvec3 run(ForceSafety& s, glm::dvec3 f, int ticks, std::int64_t& t) {
    glm::dvec3 out{0.0};
    for (int i = 0; i < ticks; ++i) out = s.filter(f, t += 1000);
    return out;
}
} // namespace

TEST(ForceSafety, NeverExceedsTheDevicesMaximum) {
    ForceSafety s(config());
    std::int64_t t = 0;
    const auto out = run(s, {100.0, 0.0, 0.0}, 2000, t);
    EXPECT_NEAR(glm::length(out), 3.0, 1e-9);
    EXPECT_GT(s.counters().clamped, 0u);
}

TEST(ForceSafety, RampsUpFromZeroAtStart) {
    ForceSafety s(config());
    std::int64_t t = 0;
    const auto after_100ms = run(s, {0.0, 0.0, 3.0}, 100, t);
    EXPECT_NEAR(after_100ms.z, 0.6, 0.01) << "100 ms into a 0.5 s ramp: 20 % of the 3 N maximum";
}

TEST(ForceSafety, StepIsRateLimited) {
    auto c = config();
    c.ramp_up_s = 0.0;
    ForceSafety s(c);
    std::int64_t t = 0;
    const auto first = s.filter({0.0, 0.0, 3.0}, t += 1000);
    EXPECT_LE(first.z, 0.3 + 1e-12) << "300 N/s allows 0.3 N per 1 ms tick";
    glm::dvec3 previous = first;
    for (int i = 0; i < 50; ++i) {
        const auto out = s.filter({0.0, 0.0, i % 2 ? 3.0 : -3.0}, t += 1000);
        EXPECT_LE(glm::length(out - previous), 0.3 + 1e-12);
        previous = out;
    }
    EXPECT_GT(s.counters().rate_limited, 0u);
}

// A physics blow-up injected on purpose: NaN and infinite requests give zero, never NaN.
TEST(ForceSafety, NonFiniteRequestBecomesZero) {
    ForceSafety s(config());
    std::int64_t t = 0;
    run(s, {1.0, 0.0, 0.0}, 1000, t);
    const auto nan = s.filter({std::nan(""), 0.0, 0.0}, t += 1000);
    EXPECT_TRUE(std::isfinite(nan.x) && std::isfinite(nan.y) && std::isfinite(nan.z));
    const auto out = run(s, {INFINITY, -INFINITY, 0.0}, 20, t);
    EXPECT_EQ(out, glm::dvec3(0.0)) << "rate-limited down to zero within 20 ticks";
    EXPECT_GT(s.counters().non_finite, 0u);
}

TEST(ForceSafety, StalledLoopRestartsFromZeroWithARamp) {
    auto c = config();
    ForceSafety s(c);
    std::int64_t t = 0;
    run(s, {0.0, 0.0, 2.0}, 1000, t);
    EXPECT_NEAR(s.last_output().z, 2.0, 1e-9);
    t += 5000; // 5 ms of silence: longer than the 2 ms watchdog
    const auto out = s.filter({0.0, 0.0, 2.0}, t);
    EXPECT_EQ(out, glm::dvec3(0.0));
    EXPECT_EQ(s.counters().stalls, 1u);
}

// The watchdog thread zeroes the device when the haptic loop stops feeding it.
TEST(ForceWatchdog, ZeroesTheDeviceWhenTheLoopStalls) {
    std::atomic<int> zeroed{0};
    ForceWatchdog watchdog([&] { zeroed.fetch_add(1); }, 2000);
    const auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(100);
    while (std::chrono::steady_clock::now() < until) {
        watchdog.feed();
        std::this_thread::sleep_for(std::chrono::microseconds(200));
    }
    // A loaded machine can oversleep 2 ms in the loop above, and a trip disarms the watchdog until the
    // next feed: count what happened so far, then feed once more, so that the stall below is a new one.
    const int while_fed = zeroed.load();
    watchdog.feed();
    // The loop stalls: 50 ms without a feed.
    const auto stall_start = std::chrono::steady_clock::now();
    while (zeroed.load() == while_fed && std::chrono::steady_clock::now() - stall_start < std::chrono::milliseconds(50)) {
        std::this_thread::sleep_for(std::chrono::microseconds(100));
    }
    EXPECT_GT(zeroed.load(), while_fed) << "the stall was caught";
    EXPECT_GE(watchdog.trips(), 1u);
    // Feeding again re-arms it; a second stall trips it again.
    watchdog.feed();
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    EXPECT_GE(watchdog.trips(), 2u);
}
