#include "engine/devices/safe_force_device.hpp"

#include <algorithm>
#include <chrono>
#include <mutex>
#include <thread>

#include "engine/core/emergency_stop.hpp"

namespace ikebana::devices {

SafeForceDevice::SafeForceDevice(std::unique_ptr<HapticDevice> inner, ForceSafetyConfig config, WallClock wall_clock_us)
    : inner_(std::move(inner)), clock_(std::move(wall_clock_us)), safety_(config) {
    // A real pushing device is zeroed on every way out, the ones that skip destructors included.
    if (inner_ && inner_->capabilities().has_force_output) {
        emergency_slot_ = add_emergency_stop({&SafeForceDevice::emergency_zero, &SafeForceDevice::zero_flushed, this});
    }
}

SafeForceDevice::~SafeForceDevice() {
    remove_emergency_stop(emergency_slot_);
    if (inner_ && inner_->capabilities().has_force_output) (void)inner_->zero_force();
}

void SafeForceDevice::emergency_zero(void* self) noexcept {
    auto* device = static_cast<SafeForceDevice*>(self);
    // The lane may have died holding the lock (an exception inside a send): wait for it a little, then
    // zero without it. A zero overtaken by nothing (the lane is gone) cannot be undone.
    bool locked = false;
    for (int i = 0; i < 50 && !(locked = device->mutex_.try_lock()); ++i) std::this_thread::sleep_for(std::chrono::microseconds(100));
    if (locked) device->safety_.zeroed();
    (void)device->inner_->zero_force();
    if (locked) device->mutex_.unlock();
}

bool SafeForceDevice::zero_flushed(void* self) noexcept {
    const WireCounts w = static_cast<SafeForceDevice*>(self)->inner_->wire();
    return w.queued == 0 || w.written >= w.queued;
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
        if (lost_) return lane_error(ErrorCode::device_lost, "the device stopped taking forces; reconnecting");
        return sample;
    }
    if (lost_) {
        // A device that cannot be opened anew stays lost (released, nothing sent) for the session.
        if (!reopening_) return lane_error(ErrorCode::device_lost, "the device stopped taking forces");
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
        silent_for_us_ = now - report_changed_at_us_;
        return lane_error(ErrorCode::device_silent, "the device has sent nothing for longer than its profile allows");
    }
    silent_for_us_ = 0;
    return sample;
}

Result<void> SafeForceDevice::send_force(glm::dvec3 force_n) {
    const std::lock_guard lock(mutex_);
    safety_.limit_max_force(inner_->max_force_now_n());
    if (lost_) return {}; // nothing to push against: poll says it is lost, and the hand has let go
    // Silent: whatever the hand asks, the force fades to zero at the rate limit.
    const glm::dvec3 out = safety_.filter(silent_ ? glm::dvec3{0.0} : force_n, clock_());
    peak_output_n_ = std::max(peak_output_n_, glm::length(out));
    auto sent = inner_->send_force(out);
    if (sent) {
        failures_in_a_row_ = 0;
        note_queued(out);
        return sent;
    }
    ++write_failures_;
    if (++failures_in_a_row_ >= lost_after_failures) {
        lost_ = true;
        safety_.reset();
        if (inner_->zero_force()) note_queued(glm::dvec3{0.0}); // as far as it still listens
        reopening_ = inner_->drop();
    }
    return sent;
}

Result<void> SafeForceDevice::zero_force() {
    const std::lock_guard lock(mutex_);
    safety_.zeroed();
    ++zeroed_;
    auto sent = inner_->zero_force();
    if (sent) note_queued(glm::dvec3{0.0});
    return sent;
}

void SafeForceDevice::note_queued(glm::dvec3 force_n) {
    const WireCounts w = inner_->wire();
    if (w.queued == 0) return; // a synchronous transport: what is queued is on the wire
    if (w.transport != queued_transport_) {
        queued_.fill({});
        wire_n_ = glm::dvec3{0.0};
        queued_transport_ = w.transport;
    }
    queued_[queued_next_] = {w.queued, force_n};
    queued_next_ = (queued_next_ + 1) % queued_kept;
}

glm::dvec3 SafeForceDevice::on_wire(glm::dvec3 queued_n) const {
    const WireCounts w = inner_->wire();
    if (w.queued == 0) return queued_n;
    if (w.transport != queued_transport_) return glm::dvec3{0.0}; // a new transport: nothing of ours written yet
    // The newest force whose report is at or before the last one written; none kept (a writer stuck
    // for 32 reports): the last one known to have gone out.
    const Queued* best = nullptr;
    for (const auto& q : queued_) {
        if (q.ticket != 0 && q.ticket <= w.written && (!best || q.ticket > best->ticket)) best = &q;
    }
    if (best) wire_n_ = best->force_n;
    return wire_n_;
}

SentForce SafeForceDevice::last_sent() const {
    const std::lock_guard lock(mutex_);
    SentForce s;
    s.queued_n = safety_.last_output();
    s.sent_n = on_wire(s.queued_n);
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

std::int64_t SafeForceDevice::silent_for_us() const {
    const std::lock_guard lock(mutex_);
    return silent_ ? silent_for_us_ : 0;
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
