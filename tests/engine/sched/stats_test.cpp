#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

#include "engine/sched/stats.hpp"

using ikebana::sched::DurationHistogram;

TEST(DurationHistogram, PercentilesWithinThreePercent) {
    std::mt19937_64 rng(3);
    std::lognormal_distribution<double> dist(10.0, 1.0); // around 20 µs with a long tail
    std::vector<std::int64_t> values;
    DurationHistogram h;
    for (int i = 0; i < 100'000; ++i) {
        const auto v = static_cast<std::int64_t>(dist(rng));
        values.push_back(v);
        h.record(v);
    }
    std::sort(values.begin(), values.end());
    for (double q : {0.5, 0.9, 0.99, 0.999}) {
        const auto exact = static_cast<double>(values[static_cast<std::size_t>(q * static_cast<double>(values.size())) - 1]);
        EXPECT_NEAR(static_cast<double>(h.percentile(q)), exact, exact * 0.035) << q;
    }
    EXPECT_EQ(h.max(), values.back());
    EXPECT_EQ(h.count(), values.size());
}

TEST(DurationHistogram, SmallValuesAreExact) {
    DurationHistogram h;
    for (int i = 0; i < 10; ++i) h.record(i);
    EXPECT_EQ(h.percentile(0.5), 4);
    EXPECT_EQ(h.percentile(1.0), 9);
    h.record(-5); // clock oddities never produce a negative bucket
    EXPECT_EQ(h.count(), 11u);
}

TEST(DurationHistogram, FractionAboveAThreshold) {
    DurationHistogram h;
    for (int i = 0; i < 900; ++i) h.record(100'000);  // 100 us
    for (int i = 0; i < 100; ++i) h.record(400'000);  // 400 us
    EXPECT_NEAR(h.fraction_above(200'000), 0.1, 1e-12);
    EXPECT_EQ(h.fraction_above(1'000'000), 0.0);
    EXPECT_EQ(DurationHistogram{}.fraction_above(0), 0.0);
}
