#include "engine/devices/force_safety.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>

namespace ikebana::devices {

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

void ForceSafety::restart(std::int64_t now_us) noexcept {
    started_ = true;
    output_ = glm::dvec3{0.0};
    level_ = 0.0;
    engaged_ = !config_.wait_for_small_force;
    small_since_us_ = -1;
    last_us_ = now_us;
}

glm::dvec3 ForceSafety::filter(glm::dvec3 requested, std::int64_t now_us) {
    if (!started_ || now_us < last_us_) {
        if (started_) ++counters_.restarts;
        restart(now_us);
    } else if (const std::int64_t gap = now_us - last_us_; gap > config_.watchdog_us) {
        ++counters_.stalls;
        if (gap >= config_.restart_after_us) {
            ++counters_.restarts;
            restart(now_us);
        } else {
            // In proportion: what the hand lost is what it gets back, at the ramp's pace.
            level_ = std::max(0.0, level_ - static_cast<double>(gap) / static_cast<double>(config_.restart_after_us));
        }
    }
    // The rate limit holds per step: after a gap the step is still one watchdog period's worth at most.
    const double dt = static_cast<double>(std::min(now_us - last_us_, config_.watchdog_us)) * 1e-6;
    last_us_ = now_us;
    if (!finite(requested)) {
        ++counters_.non_finite;
        requested = glm::dvec3{0.0};
    }
    const double asked = glm::length(requested);
    if (!engaged_) {
        if (asked <= config_.engage_below_share * config_.max_force_n) {
            if (small_since_us_ < 0) small_since_us_ = now_us;
            if (now_us - small_since_us_ >= config_.engage_hold_us) {
                engaged_ = true;
                ++counters_.engagements;
            }
        } else {
            small_since_us_ = -1;
        }
    }
    ForceHeld held = ForceHeld::none;
    if (!engaged_) {
        held = asked > 0.0 ? ForceHeld::waiting : ForceHeld::none;
        requested = glm::dvec3{0.0};
    } else {
        level_ = config_.ramp_up_s > 0.0 ? std::min(1.0, level_ + dt / config_.ramp_up_s) : 1.0;
        // The ramp scales the allowed magnitude from 0 to the maximum.
        const double limit = config_.max_force_n * level_;
        if (asked > limit) {
            if (asked > config_.max_force_n) ++counters_.clamped;
            held = asked > config_.max_force_n && level_ >= 1.0 ? ForceHeld::at_limit : ForceHeld::ramping;
            requested *= limit / asked;
        }
    }
    const glm::dvec3 step = requested - output_;
    const double max_step = config_.max_rate_n_per_s * dt;
    const double step_length = glm::length(step);
    if (step_length > max_step) {
        ++counters_.rate_limited;
        output_ += step * (max_step / step_length);
        if (held == ForceHeld::none) held = ForceHeld::rate_limited;
    } else {
        output_ = requested;
    }
    if (!finite(output_)) output_ = glm::dvec3{0.0};
    held_ = held;
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
