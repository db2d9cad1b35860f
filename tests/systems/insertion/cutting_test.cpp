#include <gtest/gtest.h>

#include <cmath>
#include <numeric>

#include "components/stem.hpp"
#include "systems/insertion/stem_cutting_system.hpp"

using namespace ikebana;
using namespace ikebana::components;

namespace {
constexpr double deg = M_PI / 180.0;

StemRestShape straight(std::size_t segments, double segment_m) {
    StemRestShape rest{};
    rest.segment_length_m.assign(segments, segment_m);
    rest.hinge_angle_rad.assign(segments - 1, 0.0);
    rest.diameter_m = 0.008;
    return rest;
}
} // namespace

// A branch bent 30 degrees 40 mm below its tip is still bent 30 degrees 40 mm below its tip once half
// of it is cut off the bottom: before, the bend stayed at the same hinge numbers, which the cut had
// laid closer together, and it moved half-way down the stem.
TEST(Cutting, ABendStaysWhereItWasOnTheStem) {
    StemRestShape rest = straight(20, 0.010);
    for (std::size_t j : {14, 15, 16}) rest.hinge_angle_rad[j] = 10 * deg; // 150, 160 and 170 mm up
    const auto moved = systems::moved_bends(rest, 0.100, 0.5);
    ASSERT_EQ(moved.size(), rest.hinge_angle_rad.size());
    const double total = std::accumulate(moved.begin(), moved.end(), 0.0);
    EXPECT_NEAR(total, 30 * deg, 0.5 * deg);
    double weighted = 0.0; // the bend's middle, from the new bottom
    for (std::size_t j = 0; j < moved.size(); ++j) weighted += moved[j] * 0.005 * static_cast<double>(j + 1);
    EXPECT_NEAR(weighted / total, 0.060, 0.002) << "160 mm up the old stem is 60 mm up the new one";
    for (std::size_t j = 0; j < 8; ++j) EXPECT_NEAR(moved[j], 0.0, 1e-12) << "the lower part stays straight: hinge " << j;
}

// An even curve keeps its curvature: each of the closer hinges turns less.
TEST(Cutting, AnEvenCurveKeepsItsCurvature) {
    StemRestShape rest = straight(10, 0.010);
    rest.hinge_angle_rad.assign(9, 1 * deg);
    const auto moved = systems::moved_bends(rest, 0.030, 0.7);
    for (double a : moved) EXPECT_NEAR(a, 0.7 * deg, 1e-12);
}
