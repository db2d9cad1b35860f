#include "engine/devices/safe_force_device.hpp"

#include <algorithm>

namespace ikebana::devices {

class SafeForceDevice::Lock {
public:
    explicit Lock(pthread_mutex_t& m) : m_(m) { pthread_mutex_lock(&m_); }
    ~Lock() { pthread_mutex_unlock(&m_); }
    Lock(const Lock&) = delete;
    Lock& operator=(const Lock&) = delete;

private:
    pthread_mutex_t& m_;
};

SafeForceDevice::SafeForceDevice(std::unique_ptr<HapticDevice> inner, ForceSafetyConfig config, WallClock wall_clock_us)
    : inner_(std::move(inner)), clock_(std::move(wall_clock_us)), safety_(config) {
    pthread_mutexattr_t attributes;
    pthread_mutexattr_init(&attributes);
    // Where priority inheritance is not supported the mutex is an ordinary one: still correct.
    (void)pthread_mutexattr_setprotocol(&attributes, PTHREAD_PRIO_INHERIT);
    pthread_mutex_init(&mutex_, &attributes);
    pthread_mutexattr_destroy(&attributes);
}

SafeForceDevice::~SafeForceDevice() { pthread_mutex_destroy(&mutex_); }

std::unique_ptr<SafeForceDevice> SafeForceDevice::on_timeline(std::unique_ptr<HapticDevice> inner, ForceSafetyConfig config) {
    auto device = std::make_unique<SafeForceDevice>(std::move(inner), config);
    SafeForceDevice* self = device.get();
    device->clock_ = [self] { return self->polled_us_.load(std::memory_order_relaxed); };
    return device;
}

Result<DeviceSample> SafeForceDevice::poll(std::int64_t now_us) {
    polled_us_.store(now_us, std::memory_order_relaxed);
    auto sample = inner_->poll(now_us);
    if (!sample) {
        const Lock lock(mutex_);
        safety_.reset();
    }
    return sample;
}

Result<void> SafeForceDevice::send_force(glm::dvec3 force_n) {
    const Lock lock(mutex_);
    safety_.limit_max_force(inner_->capabilities().max_force_n);
    const glm::dvec3 out = safety_.filter(force_n, clock_());
    peak_output_n_ = std::max(peak_output_n_, glm::length(out));
    return inner_->send_force(out);
}

Result<void> SafeForceDevice::zero_force() {
    const Lock lock(mutex_);
    safety_.reset();
    ++zeroed_;
    return inner_->zero_force();
}

ForceSafetyCounters SafeForceDevice::counters() const {
    const Lock lock(mutex_);
    return safety_.counters();
}

glm::dvec3 SafeForceDevice::last_output() const {
    const Lock lock(mutex_);
    return safety_.last_output();
}

double SafeForceDevice::peak_output_n() const {
    const Lock lock(mutex_);
    return peak_output_n_;
}

std::uint64_t SafeForceDevice::zeroed() const {
    const Lock lock(mutex_);
    return zeroed_;
}

std::unique_ptr<HapticDevice> make_force_safe(std::unique_ptr<HapticDevice> device, ForceSafetyConfig config) {
    if (!device || dynamic_cast<SafeForceDevice*>(device.get())) return device;
    if (device->capabilities().has_force_output) return std::make_unique<SafeForceDevice>(std::move(device), config);
    if (device->capabilities().on_timeline) return SafeForceDevice::on_timeline(std::move(device), config);
    return device;
}

} // namespace ikebana::devices
