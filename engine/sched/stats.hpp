#pragma once
// Per-system timing: a log-linear histogram of nanoseconds (32 sub-buckets per power of two, so any
// percentile is within about 3 % of the true value) with fixed memory and O(1) record, cheap enough to
// sit inside the 1 kHz loop. Each histogram is written by one thread only.
#include <array>
#include <cstdint>
#include <string>

namespace ikebana::sched {

class DurationHistogram {
public:
    void record(std::int64_t ns) noexcept;
    [[nodiscard]] std::uint64_t count() const noexcept { return count_; }
    [[nodiscard]] std::int64_t max() const noexcept { return max_; }
    [[nodiscard]] double mean() const noexcept { return count_ ? static_cast<double>(sum_) / static_cast<double>(count_) : 0.0; }
    // The value at quantile q in [0, 1]: the upper edge of the bucket holding it, clamped to max().
    [[nodiscard]] std::int64_t percentile(double q) const noexcept;
    void merge(const DurationHistogram& other) noexcept;
    // Share of recorded values above `ns` (bucket resolution: within about 3 % of `ns`).
    [[nodiscard]] double fraction_above(std::int64_t ns) const noexcept;

private:
    static constexpr int sub_bits = 5;
    static constexpr int sub_count = 1 << sub_bits;
    static constexpr int octaves = 44; // up to ~2^48 ns, about three days
    static std::size_t bucket_of(std::uint64_t ns) noexcept;
    static std::int64_t upper_edge(std::size_t bucket) noexcept;

    std::array<std::uint64_t, static_cast<std::size_t>(sub_count) * (octaves + 1)> buckets_{};
    std::uint64_t count_ = 0;
    std::int64_t sum_ = 0;
    std::int64_t max_ = 0;
};

struct SystemStats {
    std::uint64_t calls = 0;
    DurationHistogram duration_ns;
    DurationHistogram lateness_ns;   // real-time start minus scheduled start (0 on the deterministic clock)
    std::uint64_t missed_deadlines = 0; // started later than its next firing was due
    std::uint64_t skipped_firings = 0;  // firings dropped by the catch-up clamp
};

} // namespace ikebana::sched
