#pragma once
// The one safety layer between the simulation and anything that can push on a person's hand. Every
// device whose capabilities say it has force output is wrapped in a SafeForceDevice before a hand gets
// it (game::World::attach_device), whatever its backend: DIY, WoodenHaptics, a reconnecting wrapper.
//
//  - send_force: ForceSafety on the wall clock (clamp to the lower of our limit and the device's own,
//    rate limit, ramp from zero at start and after any stall the wall clock sees);
//  - zero_force (the watchdog's, from its own thread): zero now, and the next send starts a fresh
//    ramp from zero. A watchdog that zeroed a device must never be followed by a jump back to the
//    force from before the stall;
//  - a poll that fails (unplugged) resets the ramp too: a device that comes back starts from zero.
//
// send_force and zero_force take one mutex, so a zero can never be overtaken by a stale force. It is
// priority-inheriting: the 1 kHz thread (SCHED_FIFO) may wait on it only while the watchdog, which
// holds it for one report's write, runs at its priority.
#include <cstdint>
#include <functional>
#include <memory>
#include <pthread.h>

#include <atomic>

#include "engine/devices/force_safety.hpp"
#include "engine/devices/haptic_device.hpp"

namespace ikebana::devices {

class SafeForceDevice final : public HapticDevice {
public:
    using WallClock = std::function<std::int64_t()>; // microseconds, monotonic
    explicit SafeForceDevice(std::unique_ptr<HapticDevice> inner, ForceSafetyConfig config = {},
                             WallClock wall_clock_us = monotonic_us);
    // The safety chain on the time the device is polled with (a scripted or replayed hand): the same
    // clamp, rate limit, ramp and watchdog, deterministic, so that a recording shows what it would feel.
    [[nodiscard]] static std::unique_ptr<SafeForceDevice> on_timeline(std::unique_ptr<HapticDevice> inner, ForceSafetyConfig config = {});
    ~SafeForceDevice() override;
    SafeForceDevice(const SafeForceDevice&) = delete;
    SafeForceDevice& operator=(const SafeForceDevice&) = delete;

    [[nodiscard]] const DeviceCapabilities& capabilities() const override { return inner_->capabilities(); }
    Result<DeviceSample> poll(std::int64_t now_us) override;
    Result<void> send_force(glm::dvec3 force_n) override;
    Result<void> zero_force() override;

    [[nodiscard]] HapticDevice& inner() noexcept { return *inner_; }
    // Copies, taken under the lock (another thread may be sending).
    [[nodiscard]] ForceSafetyCounters counters() const;
    [[nodiscard]] glm::dvec3 last_output() const;
    [[nodiscard]] std::uint64_t zeroed() const;
    // The largest force that left the chain.
    [[nodiscard]] double peak_output_n() const;

private:
    class Lock;
    std::unique_ptr<HapticDevice> inner_;
    WallClock clock_;
    mutable pthread_mutex_t mutex_;
    ForceSafety safety_;
    std::uint64_t zeroed_ = 0;
    double peak_output_n_ = 0.0;
    std::atomic<std::int64_t> polled_us_{0}; // the last poll's time (the clock of on_timeline devices)
};

// `device` wrapped in a SafeForceDevice if it can push (on the wall clock) or is a scripted or replayed
// hand (on its timeline), and is not wrapped yet; otherwise unchanged.
[[nodiscard]] std::unique_ptr<HapticDevice> make_force_safe(std::unique_ptr<HapticDevice> device, ForceSafetyConfig config = {});

} // namespace ikebana::devices
