#include <gtest/gtest.h>

#include <cmath>

#include "systems/haptics/bending.hpp"

using namespace ikebana;
using namespace ikebana::systems::bending;

namespace {
constexpr double deg = M_PI / 180.0;
}

// Hand-computed: L = 100 mm, theta = 150 deg: tan 75 deg = 3.7320508; mid-span 50 / 3.7320508 mm.
TEST(Bending, Eq4MidSpanIsTheTrianglesHeight) {
    EXPECT_NEAR(displacement(0.05, 0.1, 150 * deg), 0.05 / 3.7320508075688772, 1e-12);
    EXPECT_NEAR(displacement(0.0, 0.1, 150 * deg), 0.0, 1e-15) << "supports do not move";
    EXPECT_NEAR(displacement(0.1, 0.1, 150 * deg), 0.0, 1e-15);
}

TEST(Bending, Eq4ShapeAtAQuarterSpan) {
    // x = L/4: 3/4 - 4/64 = 0.6875 of the mid-span value.
    EXPECT_NEAR(displacement(0.025, 0.1, 150 * deg), 0.6875 * 0.05 / 3.7320508075688772, 1e-12);
    EXPECT_NEAR(displacement(0.025, 0.1, 150 * deg), displacement(0.075, 0.1, 150 * deg), 1e-15) << "symmetric";
}

TEST(Bending, StraightMeansNoDisplacementAndNoForce) {
    EXPECT_EQ(displacement(0.05, 0.1, M_PI), 0.0);
    EXPECT_EQ(force(1.0, 0.1, M_PI), 0.0);
}

// Eq. 5 by hand for the sunflower stem (E = 300 MPa, d = 7.5 mm: EI = 0.046585 N m^2), L = 100 mm,
// theta = 150 deg: 24 * 0.046585 / (0.01 * 3.7320508) = 29.958 N.
TEST(Bending, Eq5ByHand) {
    const double ei = 3e8 * M_PI * std::pow(0.0075, 4) / 64.0;
    EXPECT_NEAR(force(ei, 0.1, 150 * deg), 24.0 * ei / (0.01 * 3.7320508075688772), 1e-9);
    EXPECT_NEAR(force(ei, 0.1, 150 * deg), 29.958, 0.01);
}

// Eq. 4 and Eq. 5 agree with beam theory: the central load that deflects a simply supported beam by
// the Eq. 4 mid-span is F = 48 E I delta / L^3.
TEST(Bending, Eq5IsTheBeamLoadForEq4sDeflection) {
    const double ei = 0.05;
    const double span = 0.12;
    for (double theta_deg : {100.0, 140.0, 170.0, 179.0}) {
        const double delta = displacement(0.5 * span, span, theta_deg * deg);
        EXPECT_NEAR(force(ei, span, theta_deg * deg), 48.0 * ei * delta / (span * span * span), 1e-9) << theta_deg;
    }
}

TEST(Bending, BeyondTheThresholdTheBranchStaysBent) {
    components::StemRestShape rest{std::vector<double>(10, 0.01), std::vector<double>(9, 0.0), 0.008, {}};
    // Bent 20 degrees (theta = 160) with a 12-degree threshold: 8 degrees stay, over hinges 2..5.
    const double set = apply_permanent_set(rest, 2, 5, 160 * deg, 12 * deg);
    EXPECT_NEAR(set, 8 * deg, 1e-12);
    double total = 0.0;
    for (double a : rest.hinge_angle_rad) total += a;
    EXPECT_NEAR(total, 8 * deg, 1e-12);
    EXPECT_NEAR(rest.hinge_angle_rad[3], 2 * deg, 1e-12);
    EXPECT_EQ(rest.hinge_angle_rad[0], 0.0);
    // Below the threshold nothing changes.
    EXPECT_EQ(apply_permanent_set(rest, 2, 5, 170 * deg, 12 * deg), 0.0);
}
