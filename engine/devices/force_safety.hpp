#pragma once
// Haptic devices can hurt people. Every force on its way to a device passes through ForceSafety,
// called once per haptic tick:
//  - a non-finite request (a physics blow-up) becomes zero;
//  - the magnitude is clamped to the device's maximum, scaled by the ramp's level;
//  - the change is rate-limited (no step larger than max_rate * the tick, however long the gap);
//  - after a start, an unplug or a silence, nothing is sent until the request has stayed small for a
//    moment (CHAI3D's wait-for-small-force: a hand resting inside the table asks 24 N, and engaging
//    into that would throw the handle), and then the level ramps up from zero over ramp_up;
//  - a gap between two calls longer than `watchdog` (the loop stalled) costs the ramp in proportion to
//    the gap: a 3 ms hiccup takes 3 % of the level, which climbs back within milliseconds; a stall of
//    restart_after or longer starts again from zero, with the wait.
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

#include "engine/core/monotonic_clock.hpp"
#include "engine/devices/haptic_device.hpp"

namespace ikebana::devices {

using ikebana::monotonic_us; // the wall clock every force safety decision is made on

struct ForceSafetyConfig {
    double max_force_n = 3.0;
    double max_rate_n_per_s = 300.0;     // 0.3 N per 1 ms tick at most
    double ramp_up_s = 0.5;
    std::int64_t watchdog_us = 2000;
    // A gap of this or longer restarts from zero (with the wait); a shorter one past the watchdog costs
    // gap / restart_after of the ramp's level.
    std::int64_t restart_after_us = 100'000;
    // Engaging waits until the request has stayed at or below this share of max_force_n for
    // engage_hold (false: engage at once, for tests of the ramp alone).
    bool wait_for_small_force = true;
    double engage_below_share = 0.5;
    std::int64_t engage_hold_us = 50'000;
};

struct ForceSafetyCounters {
    std::uint64_t non_finite = 0;
    std::uint64_t clamped = 0;
    std::uint64_t rate_limited = 0;
    std::uint64_t stalls = 0;      // gaps past the watchdog
    std::uint64_t restarts = 0;    // stalls long enough to start again from zero
    std::uint64_t engagements = 0; // times the output engaged after waiting for a small force
};


class ForceSafety {
public:
    explicit ForceSafety(ForceSafetyConfig config) : config_(config) {}

    // The force to send now for this request.
    glm::dvec3 filter(glm::dvec3 requested_n, std::int64_t now_us);
    // Back to zero, waiting for a small force and then ramping from zero (a device re-attached, or
    // back from a silence).
    void reset() noexcept;
    // Back to waiting for a small force and a ramp from zero, but from the output as it is: it comes
    // down at the rate limit (a device back from a silence, whose force was still fading).
    void disengage() noexcept {
        engaged_ = !config_.wait_for_small_force;
        level_ = 0.0;
        small_since_us_ = -1;
    }
    // The device was zeroed behind our back (the watchdog): the output is zero from here, so the next
    // step rises from zero at the rate limit; the ramp's level pays for the gap that caused it.
    void zeroed() noexcept { output_ = glm::dvec3{0.0}; }
    // Tightens (never loosens) the maximum: a device may report a lower limit of its own.
    void limit_max_force(double max_force_n) noexcept;

    [[nodiscard]] const ForceSafetyCounters& counters() const noexcept { return counters_; }
    [[nodiscard]] glm::dvec3 last_output() const noexcept { return output_; }
    [[nodiscard]] const ForceSafetyConfig& config() const noexcept { return config_; }
    [[nodiscard]] ForceHeld held() const noexcept { return held_; }
    [[nodiscard]] bool engaged() const noexcept { return engaged_; }
    // The ramp's level, 0 to 1: the share of max_force_n allowed now.
    [[nodiscard]] double level() const noexcept { return level_; }

private:
    void restart(std::int64_t now_us) noexcept;

    ForceSafetyConfig config_;
    ForceSafetyCounters counters_;
    glm::dvec3 output_{0.0};
    std::int64_t last_us_ = 0;
    std::int64_t small_since_us_ = -1; // since when the request has been small (-1: it is not)
    double level_ = 0.0;
    bool started_ = false;
    bool engaged_ = false;
    ForceHeld held_ = ForceHeld::none;
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
