#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "systems/insertion/pin_geometry.hpp"

using namespace ikebana;
using namespace ikebana::components;
using namespace ikebana::systems::insertion;

namespace {
// The shipped layout: 20 x 20 pins at 4 mm, pins 13 mm (11.5 trunk + 1.5 tip), base at z = 0.
Kenzan kenzan() { return Kenzan{"test", {0, 0, 0}, 0.004, 20, 20, {0.0009, 0.0115, 0.0015}, 0.008, 0.0}; }

StemEnd vertical(double x, double y, double diameter, double bottom_z) {
    return StemEnd{{x, y, bottom_z}, {0, 0, 1}, 0.5 * diameter, 0.0, 0.0, 0.05};
}
} // namespace

// The paper assumes 4 pins for a 7.5 mm stem on a 4 mm grid: that is the best case.
TEST(PinGeometry, PinsEngagedDependOnPlacement) {
    const auto k = kenzan();
    // Pins sit at +-2, +-6, ... mm (an even grid centred on the origin).
    EXPECT_EQ(engaged_pins(vertical(0.0, 0.0, 0.0075, 0.002), k).size(), 4u) << "between four pins: the best case";
    EXPECT_EQ(engaged_pins(vertical(0.002, 0.0, 0.0075, 0.002), k).size(), 2u) << "between two pins";
    EXPECT_EQ(engaged_pins(vertical(0.002, 0.002, 0.0075, 0.002), k).size(), 1u) << "centred on a pin";
    EXPECT_EQ(engaged_pins(vertical(0.002, 0.002, 0.010, 0.002), k).size(), 5u) << "a 10 mm stem on a pin reaches its 4 neighbours";
    EXPECT_EQ(engaged_pins(vertical(0.0, 0.0, 0.003, 0.002), k).size(), 0u) << "a 3 mm stem fits between the pins";
}

// Over random placements the mean number of pins in a vertical stem is its area over the pitch
// squared (pi * 3.75^2 / 16 = 2.76 for the paper's stem).
TEST(PinGeometry, MeanPinsOverRandomPlacementIsAreaOverPitchSquared) {
    const auto k = kenzan();
    std::mt19937_64 rng(4);
    std::uniform_real_distribution<double> u(-0.002, 0.002);
    double total = 0.0;
    const int n = 20000;
    for (int i = 0; i < n; ++i) total += static_cast<double>(engaged_pins(vertical(u(rng), u(rng), 0.0075, 0.002), k).size());
    const double expected = M_PI * 0.00375 * 0.00375 / (0.004 * 0.004);
    EXPECT_NEAR(total / n, expected, 0.03);
}

TEST(PinGeometry, ContactLengthSplitsIntoTrunkAndTip) {
    const auto k = kenzan();
    // Bottom 5 mm above the base: 6.5 mm of trunk and the whole 1.5 mm tip are inside.
    const auto pins = engaged_pins(vertical(0.0, 0.0, 0.0075, 0.005), k);
    ASSERT_EQ(pins.size(), 4u);
    for (const auto& p : pins) {
        EXPECT_NEAR(p.trunk_m, 0.0065, 1e-12);
        EXPECT_NEAR(p.tip_m, 0.0015, 1e-12);
    }
    // Only the tip's upper 0.5 mm reaches a bottom at 12.5 mm.
    const auto shallow = engaged_pins(vertical(0.0, 0.0, 0.0075, 0.0125), k);
    ASSERT_EQ(shallow.size(), 4u);
    EXPECT_NEAR(shallow[0].tip_m, 0.0005, 1e-12);
    EXPECT_NEAR(shallow[0].trunk_m, 0.0, 1e-12);
}

// A vertical pin through the axis of a stem at elevation theta crosses d / cos(theta) of it.
TEST(PinGeometry, ObliqueStemChordIsDiameterOverCosine) {
    const double theta = M_PI / 4.0;
    const glm::dvec3 axis{std::cos(theta), 0.0, std::sin(theta)};
    const StemEnd stem{glm::dvec3{0.0}, axis, 0.00375, 0.0, 0.0, 0.2};
    const glm::dvec3 on_axis = 0.05 * axis; // far from the bottom face
    const auto chord = vertical_chord(stem, on_axis.x, on_axis.y, stem.radius_m, 0.0, stem.length_m);
    ASSERT_TRUE(chord);
    EXPECT_NEAR(chord->length(), 0.0075 / std::cos(theta), 1e-12);
    EXPECT_FALSE(vertical_chord(stem, on_axis.x, 0.004, stem.radius_m, 0.0, stem.length_m)) << "beside the stem";
}

TEST(PinGeometry, SplitBottomGripsOnlyAboveItsSeatLoss) {
    const auto k = kenzan();
    auto stem = vertical(0.0, 0.0, 0.0075, 0.005);
    stem.seat_loss_m = 0.002;
    const auto pins = engaged_pins(stem, k);
    ASSERT_EQ(pins.size(), 4u);
    EXPECT_NEAR(pins[0].trunk_m, 0.0045, 1e-12) << "the first 2 mm of the split end hold nothing";
}

TEST(PinGeometry, LeverArmsAreMeasuredFromTheFarEdgeOfTheFootprint) {
    const auto k = kenzan();
    const double theta = M_PI / 4.0;
    // Leaning towards +x; the stem crosses the pin-top plane (13 mm) at x = 0.
    const glm::dvec3 axis{std::cos(theta), 0.0, std::sin(theta)};
    const StemEnd stem{glm::dvec3{0.0, 0.0, 0.013} - 0.013 / std::sin(theta) * axis, axis, 0.00375, 0.0, 0.0, 0.05};
    auto pins = engaged_pins(stem, k);
    ASSERT_FALSE(pins.empty());
    const glm::dvec3 edge = assign_lever_arms(stem, k, pins);
    EXPECT_NEAR(edge.x, 0.00375 / std::sin(theta), 1e-12);
    for (const auto& p : pins) {
        const double pin_x = k.pin_base(p.pin % k.columns, p.pin / k.columns).x;
        EXPECT_NEAR(p.lever_m, std::max(0.0, edge.x - pin_x), 1e-12);
    }
}

// A round kenzan has the grid's pins within its circle only: a stem pushed in at the square grid's
// corner, outside the circle, meets none; at the centre, the same as on a square kenzan.
TEST(PinGeometry, ARoundKenzanHasNoPinsOutsideItsCircle) {
    Kenzan round{"round", {0, 0, 0}, 0.004, 15, 15, {0.0009, 0.0115, 0.0015}, 0.008, 0.029};
    int pins = 0;
    for (std::int32_t c = 0; c < round.columns; ++c) {
        for (std::int32_t r = 0; r < round.rows; ++r) pins += round.has_pin(c, r) ? 1 : 0;
    }
    EXPECT_NEAR(pins, M_PI * 0.029 * 0.029 / (0.004 * 0.004), 12.0) << "the circle's area over the pitch squared";
    EXPECT_FALSE(round.has_pin(0, 0));
    EXPECT_TRUE(round.has_pin(7, 7));
    EXPECT_TRUE(round.has_pin(0, 7)) << "the pins on the axes at the edge";
    const glm::dvec3 corner = round.pin_base(0, 0);
    EXPECT_EQ(engaged_pins(vertical(corner.x + 0.002, corner.y + 0.002, 0.0075, 0.002), round).size(), 0u);
    Kenzan square = round;
    square.round_radius_m = 0.0;
    EXPECT_EQ(engaged_pins(vertical(corner.x + 0.002, corner.y + 0.002, 0.0075, 0.002), square).size(), 4u);
    EXPECT_EQ(engaged_pins(vertical(0.002, 0.002, 0.0075, 0.002), round).size(), engaged_pins(vertical(0.002, 0.002, 0.0075, 0.002), square).size());
}
