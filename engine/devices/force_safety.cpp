#include "engine/devices/force_safety.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>

namespace ikebana::devices {

namespace {
std::int64_t monotonic_ns() {
    timespec ts{};
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return std::int64_t{ts.tv_sec} * 1'000'000'000 + ts.tv_nsec;
}
} // namespace

std::int64_t monotonic_us() noexcept { return monotonic_ns() / 1000; }

namespace {
bool finite(glm::dvec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
} // namespace

void ForceSafety::reset() noexcept {
    output_ = glm::dvec3{0.0};
    started_ = false;
}

void ForceSafety::limit_max_force(double max_force_n) noexcept {
    if (max_force_n > 0.0 && max_force_n < config_.max_force_n) config_.max_force_n = max_force_n;
}

glm::dvec3 ForceSafety::filter(glm::dvec3 requested, std::int64_t now_us) {
    if (!started_ || now_us - last_us_ > config_.watchdog_us || now_us < last_us_) {
        if (started_) ++counters_.stalls;
        // A new start: from zero, ramping again.
        started_ = true;
        output_ = glm::dvec3{0.0};
        ramp_start_us_ = now_us;
        last_us_ = now_us;
    }
    const double dt = static_cast<double>(now_us - last_us_) * 1e-6;
    last_us_ = now_us;
    if (!finite(requested)) {
        ++counters_.non_finite;
        requested = glm::dvec3{0.0};
    }
    // The ramp scales the allowed magnitude from 0 to the maximum.
    const double ramp = config_.ramp_up_s > 0.0
                            ? std::clamp(static_cast<double>(now_us - ramp_start_us_) * 1e-6 / config_.ramp_up_s, 0.0, 1.0)
                            : 1.0;
    const double limit = config_.max_force_n * ramp;
    const double magnitude = glm::length(requested);
    if (magnitude > limit) {
        if (magnitude > config_.max_force_n) ++counters_.clamped;
        requested *= limit / magnitude;
    }
    const glm::dvec3 step = requested - output_;
    const double max_step = config_.max_rate_n_per_s * dt;
    const double step_length = glm::length(step);
    if (step_length > max_step) {
        ++counters_.rate_limited;
        output_ += step * (max_step / step_length);
    } else {
        output_ = requested;
    }
    if (!finite(output_)) output_ = glm::dvec3{0.0};
    return output_;
}

ForceWatchdog::ForceWatchdog(std::function<void()> zero_output, std::int64_t timeout_us)
    : zero_output_(std::move(zero_output)), timeout_us_(timeout_us), last_feed_ns_(monotonic_ns()) {
    thread_ = std::thread([this] { run(); });
}

ForceWatchdog::~ForceWatchdog() {
    stop_.store(true);
    thread_.join();
}

void ForceWatchdog::feed() noexcept { last_feed_ns_.store(monotonic_ns(), std::memory_order_release); }

void ForceWatchdog::run() {
    bool tripped = false;
    // Checks four times per timeout: a stall is caught within 1.25 timeouts plus scheduling delay.
    const auto period = std::chrono::microseconds(std::max<std::int64_t>(timeout_us_ / 4, 100));
    while (!stop_.load()) {
        std::this_thread::sleep_for(period);
        const std::int64_t silent_ns = monotonic_ns() - last_feed_ns_.load(std::memory_order_acquire);
        if (silent_ns > timeout_us_ * 1000) {
            if (!tripped) {
                zero_output_();
                trips_.fetch_add(1);
                tripped = true;
            }
        } else {
            tripped = false;
        }
    }
}

} // namespace ikebana::devices
