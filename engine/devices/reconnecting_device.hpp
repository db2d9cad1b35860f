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
// The caller's poll() only looks at the slot. The swap of the inner device is guarded against the
// watchdog's zero_force() by a priority-inheriting mutex, held for a pointer's move.
#include <atomic>
#include <condition_variable>
#include <functional>
#include <memory>
#include <mutex>
#include <thread>

#include "engine/core/pi_mutex.hpp"
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

    Opener opener_;
    DeviceCapabilities expected_;
    std::int64_t retry_us_;
    std::unique_ptr<HapticDevice> inner_; // the caller's thread's; swapped under swap_mutex_
    PiMutex swap_mutex_;                  // zero_force() comes from the watchdog's thread while poll() may swap inner_
    std::uint64_t reconnects_ = 0;
    bool ever_attached_ = false;
    // Between the caller's thread and the opener thread, one pointer each way.
    std::atomic<HapticDevice*> ready_{nullptr};   // opened, waiting to be taken
    std::atomic<HapticDevice*> retired_{nullptr}; // dropped, waiting to be closed
    std::atomic<bool> wanted_{true};              // no device attached: keep trying
    std::atomic<std::uint64_t> attempts_{0};
    std::mutex wake_mutex_;                       // the opener thread's sleep; the caller never takes it
    std::condition_variable wake_;
    bool stop_ = false;
    std::thread opener_thread_; // last: it starts when everything it uses is there
};

} // namespace ikebana::devices
