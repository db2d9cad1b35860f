#pragma once
// The q-quantile of some samples (q in [0, 1]), the nearest sample by rank: for frame and step times
// printed as p50 / p95. Zero for no samples.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace ikebana {

inline double percentile(std::vector<double> v, double q) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    return v[static_cast<std::size_t>(std::lround(q * static_cast<double>(v.size() - 1)))];
}

} // namespace ikebana
