#pragma once
// Haptic devices can hurt people. Every force on its way to a device passes through ForceSafety,
// called once per haptic tick:
//  - a non-finite request (a physics blow-up) becomes zero;
//  - the magnitude is clamped to the device's maximum;
//  - the change per second is limited (no step larger than max_rate * dt);
//  - output ramps up from zero over ramp_up at start and again after any stall;
//  - if the previous call is more than `watchdog` ago (the loop stalled), the output restarts at zero.
// The times it is given must be wall-clock times (SafeForceDevice passes the monotonic clock): the
// simulation's timeline cannot see a stall, because the firings that catch up after one are still 1 ms
// apart on it.
// And ForceWatchdog, on its own thread, sends zero to the device if the haptic loop goes silent for
// longer than `watchdog` (default 2 ms), because a stalled loop cannot zero anything itself.
#include <atomic>
#include <cstdint>
#include <functional>
#include <thread>

#include <glm/glm.hpp>

namespace ikebana::devices {

// CLOCK_MONOTONIC in microseconds: the wall clock every force safety decision is made on.
[[nodiscard]] std::int64_t monotonic_us() noexcept;

struct ForceSafetyConfig {
    double max_force_n = 3.0;
    double max_rate_n_per_s = 300.0;     // 0.3 N per 1 ms tick at most
    double ramp_up_s = 0.5;
    std::int64_t watchdog_us = 2000;
};

struct ForceSafetyCounters {
    std::uint64_t non_finite = 0;
    std::uint64_t clamped = 0;
    std::uint64_t rate_limited = 0;
    std::uint64_t stalls = 0;
};

class ForceSafety {
public:
    explicit ForceSafety(ForceSafetyConfig config) : config_(config) {}

    // The force to send now for this request.
    glm::dvec3 filter(glm::dvec3 requested_n, std::int64_t now_us);
    // Back to zero with a fresh ramp (a device re-attached, the watchdog zeroed the device).
    void reset() noexcept;
    // Tightens (never loosens) the maximum: a device may report a lower limit of its own.
    void limit_max_force(double max_force_n) noexcept;

    [[nodiscard]] const ForceSafetyCounters& counters() const noexcept { return counters_; }
    [[nodiscard]] glm::dvec3 last_output() const noexcept { return output_; }
    [[nodiscard]] const ForceSafetyConfig& config() const noexcept { return config_; }

private:
    ForceSafetyConfig config_;
    ForceSafetyCounters counters_;
    glm::dvec3 output_{0.0};
    std::int64_t last_us_ = 0;
    std::int64_t ramp_start_us_ = 0;
    bool started_ = false;
};

class ForceWatchdog {
public:
    // `zero_output` must be safe to call from the watchdog's thread (it writes a zero-force report).
    ForceWatchdog(std::function<void()> zero_output, std::int64_t timeout_us = 2000);
    ~ForceWatchdog();
    ForceWatchdog(const ForceWatchdog&) = delete;
    ForceWatchdog& operator=(const ForceWatchdog&) = delete;

    // From the haptic loop, every tick.
    void feed() noexcept;
    [[nodiscard]] std::uint64_t trips() const noexcept { return trips_.load(); }

private:
    void run();

    std::function<void()> zero_output_;
    std::int64_t timeout_us_;
    std::atomic<std::int64_t> last_feed_ns_;
    std::atomic<bool> stop_{false};
    std::atomic<std::uint64_t> trips_{0};
    std::thread thread_;
};

} // namespace ikebana::devices
