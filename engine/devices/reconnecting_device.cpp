#include "engine/devices/reconnecting_device.hpp"

#include <chrono>

namespace ikebana::devices {

ReconnectingDevice::ReconnectingDevice(Opener opener, DeviceCapabilities expected, std::int64_t retry_us)
    : opener_(std::move(opener)), expected_(std::move(expected)), retry_us_(retry_us), opener_thread_([this] { open_loop(); }) {}

ReconnectingDevice::~ReconnectingDevice() {
    {
        const std::lock_guard lock(wake_mutex_);
        stop_ = true;
    }
    wake_.notify_one();
    opener_thread_.join();
    delete ready_.exchange(nullptr);
    HapticDevice* retired = nullptr;
    while (retired_.pop(retired)) delete retired;
}

const DeviceCapabilities& ReconnectingDevice::capabilities() const { return expected_; }

double ReconnectingDevice::max_force_now_n() const {
    const std::lock_guard lock(swap_mutex_);
    return inner_ ? inner_->max_force_now_n() : expected_.max_force_n;
}

WireCounts ReconnectingDevice::wire() const {
    const std::lock_guard lock(swap_mutex_);
    return inner_ ? inner_->wire() : WireCounts{};
}

IoPriority ReconnectingDevice::io_priority() const {
    const std::lock_guard lock(swap_mutex_);
    return inner_ ? inner_->io_priority() : IoPriority::none;
}

void ReconnectingDevice::open_loop() {
    std::unique_lock lock(wake_mutex_);
    while (!stop_) {
        lock.unlock();
        // Closing a dropped device may block (hid_close): here, never on the caller's thread.
        HapticDevice* retired = nullptr;
        while (retired_.pop(retired)) delete retired;
        bool retry_later = false;
        if (wanted_.load(std::memory_order_acquire) && ready_.load(std::memory_order_acquire) == nullptr) {
            attempts_.fetch_add(1, std::memory_order_relaxed);
            auto opened = opener_();
            if (opened) {
                // Not wanted any more *before* it is handed over: once the caller holds it, only the
                // caller may say it is wanted again (a store after the hand-over could undo that).
                wanted_.store(false, std::memory_order_release);
                ready_.store(std::move(opened).value().release(), std::memory_order_release);
            } else {
                retry_later = true;
            }
        }
        lock.lock();
        if (stop_) break;
        // Asleep until the retry is due, or 50 ms (a device the caller dropped is seen within that).
        const auto wait = retry_later ? std::chrono::microseconds(std::max<std::int64_t>(retry_us_, 1000)) : std::chrono::microseconds(50'000);
        wake_.wait_for(lock, wait, [&] {
            return stop_ || (!retry_later && wanted_.load(std::memory_order_acquire)) || retired_.size() != 0;
        });
    }
}

void ReconnectingDevice::detach() {
    std::unique_ptr<HapticDevice> old;
    {
        const std::lock_guard lock(swap_mutex_);
        old = std::move(inner_);
    }
    // The opener thread closes it. Its queue may still hold devices it has not reached (it empties it
    // only between two openings); full, this one waits here for the next poll to hand it over.
    hand_over_retired(std::move(old));
    wanted_.store(true, std::memory_order_release);
    // No notify: glibc's takes the condition variable's internal lock, which is not priority
    // inheriting. The opener thread looks again within its 50 ms sleep.
}

void ReconnectingDevice::hand_over_retired(std::unique_ptr<HapticDevice> device) {
    if (parked_ && retired_.push(parked_.get())) (void)parked_.release();
    if (!device) return;
    if (!parked_ && retired_.push(device.get())) {
        (void)device.release();
        return;
    }
    // Eight closes behind and one parked already: never seen; kept rather than closed here.
    if (!parked_) parked_ = std::move(device);
    else (void)device.release(); // leaked rather than closed on the 1 kHz thread
}

Result<DeviceSample> ReconnectingDevice::poll(std::int64_t now_us) {
    if (parked_) hand_over_retired(nullptr);
    if (!inner_) {
        HapticDevice* ready = ready_.exchange(nullptr, std::memory_order_acq_rel);
        if (!ready) return lane_error(ErrorCode::device_error, "disconnected");
        {
            const std::lock_guard lock(swap_mutex_);
            inner_.reset(ready);
        }
        if (ever_attached_) ++reconnects_;
        ever_attached_ = true;
    }
    auto sample = inner_->poll(now_us);
    if (!sample) detach();
    return sample;
}

bool ReconnectingDevice::drop() {
    if (inner_) detach();
    return true;
}

Result<void> ReconnectingDevice::send_force(glm::dvec3 force_n) {
    // The same lock as zero_force(): the watchdog's zero and this force must not interleave on the wire.
    const std::lock_guard lock(swap_mutex_);
    if (!inner_) return {}; // nothing to push against: the hand is released and its force zero
    return inner_->send_force(force_n);
}

Result<void> ReconnectingDevice::zero_force() {
    const std::lock_guard lock(swap_mutex_);
    return inner_ ? inner_->zero_force() : Result<void>{};
}

} // namespace ikebana::devices
