#include "engine/sched/stats.hpp"

#include <algorithm>
#include <bit>
#include <cmath>

namespace ikebana::sched {

std::size_t DurationHistogram::bucket_of(std::uint64_t ns) noexcept {
    if (ns < static_cast<std::uint64_t>(sub_count)) return static_cast<std::size_t>(ns);
    const int msb = static_cast<int>(std::bit_width(ns)) - 1; // >= sub_bits
    const int octave = std::min(msb - sub_bits + 1, octaves);
    const auto sub = static_cast<std::size_t>((ns >> (msb - sub_bits)) & (sub_count - 1));
    return static_cast<std::size_t>(octave) * sub_count + sub;
}

std::int64_t DurationHistogram::upper_edge(std::size_t bucket) noexcept {
    const auto octave = static_cast<int>(bucket / sub_count);
    const auto sub = static_cast<std::int64_t>(bucket % sub_count);
    if (octave == 0) return sub;
    const int shift = octave - 1;
    return ((sub_count + sub + 1) << shift) - 1;
}

void DurationHistogram::record(std::int64_t ns) noexcept {
    const auto v = static_cast<std::uint64_t>(std::max<std::int64_t>(ns, 0));
    ++buckets_[bucket_of(v)];
    ++count_;
    sum_ += static_cast<std::int64_t>(v);
    max_ = std::max(max_, static_cast<std::int64_t>(v));
}

std::int64_t DurationHistogram::percentile(double q) const noexcept {
    if (count_ == 0) return 0;
    const auto rank = static_cast<std::uint64_t>(std::ceil(std::clamp(q, 0.0, 1.0) * static_cast<double>(count_)));
    std::uint64_t seen = 0;
    for (std::size_t b = 0; b < buckets_.size(); ++b) {
        seen += buckets_[b];
        if (seen >= std::max<std::uint64_t>(rank, 1)) return std::min(upper_edge(b), max_);
    }
    return max_;
}

void DurationHistogram::merge(const DurationHistogram& other) noexcept {
    for (std::size_t b = 0; b < buckets_.size(); ++b) buckets_[b] += other.buckets_[b];
    count_ += other.count_;
    sum_ += other.sum_;
    max_ = std::max(max_, other.max_);
}

} // namespace ikebana::sched

namespace ikebana::sched {

double DurationHistogram::fraction_above(std::int64_t ns) const noexcept {
    if (count_ == 0) return 0.0;
    std::uint64_t above = 0;
    for (std::size_t b = 0; b < buckets_.size(); ++b) {
        if (upper_edge(b) > ns) above += buckets_[b];
    }
    return static_cast<double>(above) / static_cast<double>(count_);
}

} // namespace ikebana::sched
