#pragma once
// CLOCK_MONOTONIC: the wall clock every deadline of the real-time loop and every force-safety decision
// is made on (the simulation's timeline cannot see a stall). One definition for the scheduler and the
// devices.
#include <cstdint>
#include <ctime>

namespace ikebana {

[[nodiscard]] inline std::int64_t monotonic_ns() noexcept {
    timespec ts{};
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return std::int64_t{ts.tv_sec} * 1'000'000'000 + ts.tv_nsec;
}

[[nodiscard]] inline std::int64_t monotonic_us() noexcept { return monotonic_ns() / 1000; }

} // namespace ikebana
