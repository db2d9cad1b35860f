#include "engine/devices/reconnecting_device.hpp"

namespace ikebana::devices {

ReconnectingDevice::ReconnectingDevice(Opener opener, DeviceCapabilities expected, std::int64_t retry_us)
    : opener_(std::move(opener)), expected_(std::move(expected)), retry_us_(retry_us) {}

const DeviceCapabilities& ReconnectingDevice::capabilities() const { return inner_ ? inner_->capabilities() : expected_; }

Result<DeviceSample> ReconnectingDevice::poll(std::int64_t now_us) {
    if (!inner_) {
        if (now_us < next_try_us_) return make_error(ErrorCode::device_error, expected_.name + ": disconnected");
        auto opened = opener_();
        if (!opened) {
            next_try_us_ = now_us + retry_us_;
            return std::move(opened).error();
        }
        std::lock_guard lock(inner_mutex_);
        inner_ = std::move(opened).value();
        if (ever_attached_) ++reconnects_;
        ever_attached_ = true;
    }
    auto sample = inner_->poll(now_us);
    if (!sample) {
        std::lock_guard lock(inner_mutex_);
        inner_.reset();
        next_try_us_ = now_us + retry_us_;
    }
    return sample;
}

Result<void> ReconnectingDevice::send_force(glm::dvec3 force_n) {
    // The same lock as zero_force(): the watchdog's zero and this force must not interleave on the wire.
    std::lock_guard lock(inner_mutex_);
    if (!inner_) return {}; // nothing to push against: the hand is released and its force zero
    return inner_->send_force(force_n);
}

} // namespace ikebana::devices

namespace ikebana::devices {

Result<void> ReconnectingDevice::zero_force() {
    std::lock_guard lock(inner_mutex_);
    return inner_ ? inner_->zero_force() : Result<void>{};
}

} // namespace ikebana::devices
