#pragma once
// The one safety layer between the simulation and anything that can push on a person's hand. Every
// device whose capabilities say it has force output is wrapped in a SafeForceDevice before a hand gets
// it (game::World::attach_device), whatever its backend: DIY, WoodenHaptics, a reconnecting wrapper.
//
//  - send_force: ForceSafety on the wall clock (clamp to the lower of our limit and the device's own,
//    rate limit, wait for a small force before engaging, ramp from zero, a stall costs the ramp in
//    proportion to its length);
//  - zero_force (the watchdog's, from its own thread): zero now; the next send rises from zero at the
//    rate limit. A watchdog that zeroed a device must never be followed by a jump back to the force
//    from before the stall;
//  - poll: a read that fails (unplugged) resets the chain: a device that comes back waits for a small
//    force and ramps from zero. A device whose profile says how often it reports and that has sent
//    nothing new for longer (plugged in, but hung) is *silent*: poll fails with device_silent (the hand
//    lets go), its force fades to zero at the rate limit, and it comes back through the wait and the
//    ramp when reports resume;
//  - a write that fails is counted; `lost_after_failures` in a row and the device is lost: zeroed (as
//    far as it still listens), dropped (a reconnecting device reopens it off this thread), and poll
//    fails with device_lost until it has been reattached.
//
// send_force, zero_force and the swap of a reconnecting device's inner device take one
// priority-inheriting mutex, so a zero can never be overtaken by a stale force: the 1 kHz thread
// (SCHED_FIFO) waits on it only while the watchdog holds it for one report's write, and then the
// watchdog runs at its priority.
#include <array>
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>

#include "engine/core/pi_mutex.hpp"
#include "engine/devices/force_safety.hpp"
#include "engine/devices/haptic_device.hpp"

namespace ikebana::devices {

class SafeForceDevice final : public HapticDevice {
public:
    static constexpr int lost_after_failures = 3;
    using WallClock = std::function<std::int64_t()>; // microseconds, monotonic
    explicit SafeForceDevice(std::unique_ptr<HapticDevice> inner, ForceSafetyConfig config = {},
                             WallClock wall_clock_us = monotonic_us);
    // The safety chain on the time the device is polled with (a scripted or replayed hand): the same
    // clamp, rate limit, ramp and watchdog, deterministic, so that a recording shows what it would feel.
    [[nodiscard]] static std::unique_ptr<SafeForceDevice> on_timeline(std::unique_ptr<HapticDevice> inner, ForceSafetyConfig config = {});
    // Zeroes the device as it goes: nothing pushes once its chain is gone.
    ~SafeForceDevice() override;
    SafeForceDevice(const SafeForceDevice&) = delete;
    SafeForceDevice& operator=(const SafeForceDevice&) = delete;

    [[nodiscard]] const DeviceCapabilities& capabilities() const override { return inner_->capabilities(); }
    [[nodiscard]] double max_force_now_n() const override { return inner_->max_force_now_n(); }
    [[nodiscard]] WireCounts wire() const override { return inner_->wire(); }
    [[nodiscard]] IoPriority io_priority() const override { return inner_->io_priority(); }
    Result<DeviceSample> poll(std::int64_t now_us) override;
    Result<void> send_force(glm::dvec3 force_n) override;
    Result<void> zero_force() override;
    [[nodiscard]] SentForce last_sent() const override;

    [[nodiscard]] HapticDevice& inner() noexcept { return *inner_; }
    // Copies, taken under the lock (another thread may be sending).
    [[nodiscard]] ForceSafetyCounters counters() const;
    [[nodiscard]] glm::dvec3 last_output() const;
    [[nodiscard]] std::uint64_t zeroed() const;
    // The largest force that left the chain.
    [[nodiscard]] double peak_output_n() const;
    [[nodiscard]] std::uint64_t write_failures() const;
    [[nodiscard]] bool silent() const;
    // How long a silent device has sent nothing (0 when it is not silent).
    [[nodiscard]] std::int64_t silent_for_us() const;
    [[nodiscard]] bool lost() const;

private:
    // The forces let out, by the transport's number for the report that carried each, so that the
    // force on the wire is known from the number of the last report written (WireCounts).
    struct Queued {
        std::uint64_t ticket = 0;
        glm::dvec3 force_n{0.0};
    };
    static constexpr std::size_t queued_kept = 32;
    void note_queued(glm::dvec3 force_n); // under mutex_
    [[nodiscard]] glm::dvec3 on_wire(glm::dvec3 queued_n) const; // under mutex_
    static void emergency_zero(void* self) noexcept;  // engine/core/emergency_stop.hpp
    static bool zero_flushed(void* self) noexcept;

    std::unique_ptr<HapticDevice> inner_;
    WallClock clock_;
    mutable PiMutex mutex_;
    ForceSafety safety_;
    std::uint64_t zeroed_ = 0;
    double peak_output_n_ = 0.0;
    std::atomic<std::int64_t> polled_us_{0}; // the last poll's time (the clock of on_timeline devices)
    // Silence: the report time the last sample carried, and when (on our clock) it last changed.
    bool reporting_ = false;                  // a fresh sample has been seen since (re)attaching
    std::int64_t last_report_us_ = 0;
    std::int64_t report_changed_at_us_ = 0;
    bool silent_ = false;
    std::int64_t silent_for_us_ = 0;
    // Lost: writes failed `lost_after_failures` times in a row; cleared once a reopened device answers.
    std::uint64_t write_failures_ = 0;
    int failures_in_a_row_ = 0;
    bool lost_ = false;
    bool reopening_ = false; // the lost device is being opened anew: its next answer is the new one's
    std::array<Queued, queued_kept> queued_{};
    std::size_t queued_next_ = 0;
    const void* queued_transport_ = nullptr;
    mutable glm::dvec3 wire_n_{0.0};
    std::size_t emergency_slot_ = static_cast<std::size_t>(-1);
};

// `device` wrapped in a SafeForceDevice if it can push (on the wall clock) or is a scripted or replayed
// hand (on its timeline), and is not wrapped yet; otherwise unchanged.
[[nodiscard]] std::unique_ptr<HapticDevice> make_force_safe(std::unique_ptr<HapticDevice> device, ForceSafetyConfig config = {});

} // namespace ikebana::devices
