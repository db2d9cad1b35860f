#pragma once
// A device that may be unplugged and plugged back: while its inner device answers, it is that device;
// when a read fails it drops it, reports the failure (the hand releases and zeroes its force), and
// opens it again as soon as it can.
//
// Opening a HID device enumerates the bus and opens a file: milliseconds, or hundreds of them on a
// stalled hub. None of it happens on the caller's thread (the 1 kHz loop): a thread of this device's
// own tries the opener every `retry_us` while no device is attached and hands a ready one over through
// an atomic slot; a dropped device goes back to that thread through another slot to be closed there
// (seen within the thread's 50 ms sleep: waking it would take a lock that is not priority inheriting).
// That way back is a queue, not one slot: an opener thread that closes late never leaves the caller
// to close a device itself (hid_close and a join of the transport's thread on the 1 kHz thread).
//
// capabilities() are the expected ones, always: another thread (the HUD, the watchdog's owner) may
// hold the reference while the inner device is swapped and deleted. What changes while a device is
// attached (its reported force limit, its wire) is asked through the calls that take the swap lock.
// The caller's poll() only looks at the slot. The swap of the inner device is guarded against the
// watchdog's zero_force() by a priority-inheriting mutex, held for a pointer's move.
#include <atomic>
#include <condition_variable>
#include <functional>
#include <memory>
#include <mutex>
#include <thread>

#include "engine/core/pi_mutex.hpp"
#include "engine/core/spsc_ring.hpp"
#include "engine/devices/haptic_device.hpp"

namespace ikebana::devices {

class ReconnectingDevice final : public HapticDevice {
public:
    using Opener = std::function<Result<std::unique_ptr<HapticDevice>>()>;
    // The opener runs on the device's own thread only. The first attempt starts at once.
    ReconnectingDevice(Opener opener, DeviceCapabilities expected, std::int64_t retry_us = 500'000);
    ~ReconnectingDevice() override;
    ReconnectingDevice(const ReconnectingDevice&) = delete;
    ReconnectingDevice& operator=(const ReconnectingDevice&) = delete;

    [[nodiscard]] const DeviceCapabilities& capabilities() const override;
    [[nodiscard]] double max_force_now_n() const override;
    [[nodiscard]] WireCounts wire() const override;
    [[nodiscard]] IoPriority io_priority() const override;
    Result<DeviceSample> poll(std::int64_t now_us) override;
    Result<void> send_force(glm::dvec3 force_n) override;
    Result<void> zero_force() override;
    bool drop() override;

    [[nodiscard]] bool attached() const noexcept { return inner_ != nullptr; }
    [[nodiscard]] std::uint64_t reconnects() const noexcept { return reconnects_; }
    // How many times the opener has been tried (the opener thread's count; for tests and --stats).
    [[nodiscard]] std::uint64_t attempts() const noexcept { return attempts_.load(std::memory_order_relaxed); }

private:
    void open_loop();
    void detach();
    void hand_over_retired(std::unique_ptr<HapticDevice> device); // the caller's thread

    Opener opener_;
    DeviceCapabilities expected_;
    std::int64_t retry_us_;
    std::unique_ptr<HapticDevice> inner_; // the caller's thread's; swapped under swap_mutex_
    mutable PiMutex swap_mutex_;          // zero_force() comes from the watchdog's thread while poll() may swap inner_
    std::uint64_t reconnects_ = 0;
    bool ever_attached_ = false;
    // Between the caller's thread and the opener thread, one pointer each way.
    std::atomic<HapticDevice*> ready_{nullptr};   // opened, waiting to be taken
    SpscRing<HapticDevice*> retired_{8};          // dropped, waiting to be closed (caller -> opener thread)
    std::unique_ptr<HapticDevice> parked_;        // dropped while that queue was full: handed over at the next poll
    std::atomic<bool> wanted_{true};              // no device attached: keep trying
    std::atomic<std::uint64_t> attempts_{0};
    std::mutex wake_mutex_;                       // the opener thread's sleep; the caller never takes it
    std::condition_variable wake_;
    bool stop_ = false;
    std::thread opener_thread_; // last: it starts when everything it uses is there
};

} // namespace ikebana::devices
