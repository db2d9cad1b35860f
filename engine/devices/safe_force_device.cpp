#include "engine/devices/safe_force_device.hpp"

#include <algorithm>
#include <mutex>

namespace ikebana::devices {

SafeForceDevice::SafeForceDevice(std::unique_ptr<HapticDevice> inner, ForceSafetyConfig config, WallClock wall_clock_us)
    : inner_(std::move(inner)), clock_(std::move(wall_clock_us)), safety_(config) {}

SafeForceDevice::~SafeForceDevice() {
    if (inner_ && inner_->capabilities().has_force_output) (void)inner_->zero_force();
}

std::unique_ptr<SafeForceDevice> SafeForceDevice::on_timeline(std::unique_ptr<HapticDevice> inner, ForceSafetyConfig config) {
    auto device = std::make_unique<SafeForceDevice>(std::move(inner), config);
    SafeForceDevice* self = device.get();
    device->clock_ = [self] { return self->polled_us_.load(std::memory_order_relaxed); };
    return device;
}

Result<DeviceSample> SafeForceDevice::poll(std::int64_t now_us) {
    polled_us_.store(now_us, std::memory_order_relaxed);
    auto sample = inner_->poll(now_us);
    const std::lock_guard lock(mutex_);
    if (!sample) {
        // Unplugged (or, after a loss, being reopened): zero now, and a fresh start when it is back.
        safety_.reset();
        reporting_ = false;
        silent_ = false;
        if (lost_) return make_error(ErrorCode::device_lost, inner_->capabilities().name + ": stopped taking forces; reconnecting");
        return sample;
    }
    if (lost_) {
        // A device that cannot be opened anew stays lost (released, nothing sent) for the session.
        if (!reopening_) return make_error(ErrorCode::device_lost, inner_->capabilities().name + ": stopped taking forces");
        // The reopened device answers: it starts over, from the wait and the ramp.
        lost_ = false;
        reopening_ = false;
        failures_in_a_row_ = 0;
        safety_.reset();
        reporting_ = false;
    }
    const std::int64_t silent_after = inner_->capabilities().silent_after_us;
    if (silent_after <= 0) return sample;
    const std::int64_t now = clock_();
    const std::int64_t report = sample->report_time_us();
    if (!reporting_ || report != last_report_us_) {
        if (silent_) {
            // Reports again: back through the wait for a small force and the ramp; what is still
            // fading goes on fading at the rate limit (a reset would drop it in one step).
            silent_ = false;
            safety_.disengage();
        }
        reporting_ = true;
        last_report_us_ = report;
        report_changed_at_us_ = now;
    } else if (now - report_changed_at_us_ > silent_after) {
        silent_ = true;
    }
    if (silent_) {
        return make_error(ErrorCode::device_silent, inner_->capabilities().name + ": sent nothing for " +
                                                        std::to_string((now - report_changed_at_us_) / 1000) + " ms");
    }
    return sample;
}

Result<void> SafeForceDevice::send_force(glm::dvec3 force_n) {
    const std::lock_guard lock(mutex_);
    safety_.limit_max_force(inner_->capabilities().max_force_n);
    if (lost_) return {}; // nothing to push against: poll says it is lost, and the hand has let go
    // Silent: whatever the hand asks, the force fades to zero at the rate limit.
    const glm::dvec3 out = safety_.filter(silent_ ? glm::dvec3{0.0} : force_n, clock_());
    peak_output_n_ = std::max(peak_output_n_, glm::length(out));
    auto sent = inner_->send_force(out);
    if (sent) {
        failures_in_a_row_ = 0;
        return sent;
    }
    ++write_failures_;
    if (++failures_in_a_row_ >= lost_after_failures) {
        lost_ = true;
        safety_.reset();
        (void)inner_->zero_force(); // as far as it still listens
        reopening_ = inner_->drop();
    }
    return sent;
}

Result<void> SafeForceDevice::zero_force() {
    const std::lock_guard lock(mutex_);
    safety_.zeroed();
    ++zeroed_;
    return inner_->zero_force();
}

SentForce SafeForceDevice::last_sent() const {
    const std::lock_guard lock(mutex_);
    SentForce s;
    s.sent_n = safety_.last_output();
    s.max_force_n = safety_.config().max_force_n;
    s.held = silent_ || lost_ ? ForceHeld::fading : safety_.held();
    s.pushes = true;
    return s;
}

ForceSafetyCounters SafeForceDevice::counters() const {
    const std::lock_guard lock(mutex_);
    return safety_.counters();
}

glm::dvec3 SafeForceDevice::last_output() const {
    const std::lock_guard lock(mutex_);
    return safety_.last_output();
}

double SafeForceDevice::peak_output_n() const {
    const std::lock_guard lock(mutex_);
    return peak_output_n_;
}

std::uint64_t SafeForceDevice::zeroed() const {
    const std::lock_guard lock(mutex_);
    return zeroed_;
}

std::uint64_t SafeForceDevice::write_failures() const {
    const std::lock_guard lock(mutex_);
    return write_failures_;
}

bool SafeForceDevice::silent() const {
    const std::lock_guard lock(mutex_);
    return silent_;
}

bool SafeForceDevice::lost() const {
    const std::lock_guard lock(mutex_);
    return lost_;
}

std::unique_ptr<HapticDevice> make_force_safe(std::unique_ptr<HapticDevice> device, ForceSafetyConfig config) {
    if (!device || dynamic_cast<SafeForceDevice*>(device.get())) return device;
    if (device->capabilities().has_force_output) return std::make_unique<SafeForceDevice>(std::move(device), config);
    if (device->capabilities().on_timeline) return SafeForceDevice::on_timeline(std::move(device), config);
    return device;
}

} // namespace ikebana::devices
