#pragma once
// A device that may be unplugged and plugged back: while its inner device answers, it is that device;
// when a read fails it drops it, reports the failure (the hand releases and zeroes its force), and
// tries to open it again every `retry_us` until it answers again.
#include <functional>
#include <memory>
#include <mutex>

#include "engine/devices/haptic_device.hpp"

namespace ikebana::devices {

class ReconnectingDevice final : public HapticDevice {
public:
    using Opener = std::function<Result<std::unique_ptr<HapticDevice>>()>;
    ReconnectingDevice(Opener opener, DeviceCapabilities expected, std::int64_t retry_us = 500'000);

    [[nodiscard]] const DeviceCapabilities& capabilities() const override;
    Result<DeviceSample> poll(std::int64_t now_us) override;
    Result<void> send_force(glm::dvec3 force_n) override;
    Result<void> zero_force() override;

    [[nodiscard]] bool attached() const noexcept { return inner_ != nullptr; }
    [[nodiscard]] std::uint64_t reconnects() const noexcept { return reconnects_; }

private:
    Opener opener_;
    DeviceCapabilities expected_;
    std::int64_t retry_us_;
    std::unique_ptr<HapticDevice> inner_;
    std::mutex inner_mutex_; // zero_force() comes from the watchdog's thread while poll() may drop inner_
    std::int64_t next_try_us_ = 0;
    std::uint64_t reconnects_ = 0;
    bool ever_attached_ = false;
};

} // namespace ikebana::devices
