#include <gtest/gtest.h>

#include <cmath>

#include "systems/physics/part_attachment.hpp"
#include "systems/physics/stem_builder.hpp"
#include "systems/physics/stem_dynamics.hpp"
#include "systems/physics/stem_frame.hpp"

using namespace ikebana;
using namespace ikebana::systems::physics;

namespace {
constexpr double dt = 1e-3;
constexpr double deg = 3.14159265358979323846 / 180.0;
const glm::dvec3 no_gravity{0.0};

StemSpec willow_spec() {
    StemSpec s; // a green willow shoot: 300 mm of 5 mm, E 4 GPa
    s.segments = 20;
    s.length_m = 0.30;
    s.diameter_m = 0.005;
    s.youngs_modulus_pa = 4.0e9;
    s.stem_mass_kg = 0.006;
    return s;
}

// One tick as the schedule runs it: the stem's step with its frame, then the frame's update.
bool tick(BuiltStem& stem, StemSolverScratch& scratch, FrameScratch& frame_scratch) {
    if (!step_stem(stem.points, stem.rest, stem.springs, nullptr, no_gravity, dt, scratch, &stem.frame)) return false;
    update_frame(stem.frame, stem.points.position_m, stem.rest, stem.springs.hinge_nm_per_rad, frame_scratch);
    return true;
}

// Where the tip lies off the line of the two held bottom points, as an angle about that line.
double tip_side_rad(const BuiltStem& stem) {
    const auto& x = stem.points.position_m;
    const glm::dvec3 axis = glm::normalize(x[1] - x[0]);
    const glm::dvec3 off = x.back() - x[0] - glm::dot(x.back() - x[0], axis) * axis;
    return std::atan2(off.y, off.x);
}

double total_twist(const BuiltStem& stem) {
    double sum = 0.0;
    for (std::size_t i = 1; i < stem.frame.director.size(); ++i) sum += twist_at(stem.frame, stem.points.position_m, i);
    return sum;
}
} // namespace

// A torsion test: the bottom segment held, a moment T about the top one. Twist is uniform along the
// stem and comes to T L / (G J), L being the length it spans (from the first segment's middle to the
// last one's), G J = E I / (1 + nu) for a round section.
TEST(StemFrame, ATwistingMomentTwistsTheStemByTLOverGJ) {
    BuiltStem stem = build_stem(willow_spec());
    const double gj = 4.0e9 * second_moment_of_area(0.005) / 1.3;
    EXPECT_NEAR(stem.twist_stiffness_nm2, gj, 1e-9 * gj);
    const double l = 0.30 / 20;
    const double span = 19 * l;
    const double moment = 0.3 * gj / span; // 0.3 rad end to end
    FrameScratch scratch;
    const glm::dvec3 held = stem.frame.director.front();
    for (int t = 0; t < 20; ++t) {
        stem.frame.held.front() = 1;
        stem.frame.held_director.front() = held;
        stem.frame.external_twist_nm.back() = moment;
        update_frame(stem.frame, stem.points.position_m, stem.rest, stem.springs.hinge_nm_per_rad, scratch);
    }
    EXPECT_NEAR(total_twist(stem), moment * span / gj, 0.02 * 0.3);
    for (std::size_t i = 1; i < 20; ++i) EXPECT_NEAR(twist_at(stem.frame, stem.points.position_m, i), 0.3 / 19, 0.02 * 0.3 / 19) << "hinge " << i;
    EXPECT_NEAR(glm::length(stem.frame.director.front() - held), 0.0, 1e-12) << "the held segment stays as held";
    // Let go of the moment: the twist springs back (nothing holds it but the bottom).
    for (int t = 0; t < 20; ++t) {
        stem.frame.held.front() = 1;
        stem.frame.held_director.front() = held;
        update_frame(stem.frame, stem.points.position_m, stem.rest, stem.springs.hinge_nm_per_rad, scratch);
    }
    EXPECT_NEAR(total_twist(stem), 0.0, 1e-6);
}

// A bend with a direction on the stem (a permanent set, a species' natural curve: build_stem gives it
// one) turns with the stem when the stem is turned about its own axis; a bend without one (the rest
// shape's directions zeroed: the model keeps that case) stays where its shape put it, the stem turning
// under it. The bottom two points are held as a hand holds them.
TEST(StemFrame, ABendWithADirectionTurnsWithTheStemWhenTheHandTurnsIt) {
    for (const bool directed : {true, false}) {
        StemSpec spec = willow_spec();
        spec.rest_bend_rad = 40 * deg;
        spec.bend_towards = {1, 0, 0};
        BuiltStem stem = build_stem(spec);
        if (!directed) stem.rest.hinge_bend_direction.assign(stem.rest.hinge_angle_rad.size(), glm::dvec2{0.0});
        stem.points.pinned[0] = stem.points.pinned[1] = 1;
        StemSolverScratch scratch;
        FrameScratch frame_scratch;
        const glm::dvec3 start = stem.frame.director.front();
        const double side_before = tip_side_rad(stem);
        EXPECT_NEAR(side_before, 0.0, 1e-9) << "bent toward +x";
        // The hand turns 90 degrees about the stem in half a second, then holds still for a second.
        for (int t = 0; t < 1500; ++t) {
            const double turned = std::min(1.0, t / 500.0) * 90 * deg;
            const glm::dvec3 axis = glm::normalize(stem.points.position_m[1] - stem.points.position_m[0]);
            stem.frame.held.front() = 1;
            stem.frame.held_director.front() = std::cos(turned) * start + std::sin(turned) * glm::cross(axis, start);
            ASSERT_TRUE(tick(stem, scratch, frame_scratch)) << t;
        }
        const double bow = glm::length(glm::dvec2(stem.points.position_m.back() - stem.points.position_m[0]));
        EXPECT_GT(bow, 0.05) << "still bent";
        if (directed) EXPECT_NEAR(tip_side_rad(stem), 90 * deg, 3 * deg) << "the bend went round with the bark";
        else EXPECT_NEAR(tip_side_rad(stem), 0.0, 3 * deg) << "a bend without a direction stays where it lay";
    }
}

// With nothing pushing and no damping, the stem's energy never grows: the frame's update moves the rest
// bends only toward less energy, and the step dissipates.
TEST(StemFrame, AFreeBentStemsEnergyNeverGrowsWithoutInput) {
    StemSpec spec = willow_spec();
    spec.rest_bend_rad = 60 * deg;
    spec.stiffness_damping_s = 0.0;
    spec.air_drag_per_s = 0.0;
    BuiltStem stem = build_stem(spec);
    rest_bends_from_shape(stem.points.position_m, stem.frame, stem.rest);
    // Knocked: the tip given a sideways and the middle an upward speed, out of the bend's plane.
    stem.points.velocity_m_s.back() = {0.0, 0.5, 0.0};
    stem.points.velocity_m_s[10] = {0.3, 0.0, 0.2};
    StemSolverScratch scratch;
    FrameScratch frame_scratch;
    const double start = stem_energy(stem.points, stem.rest, stem.springs, nullptr, no_gravity, &stem.frame).total();
    ASSERT_GT(start, 0.0);
    double previous = start;
    for (int t = 0; t < 2000; ++t) {
        ASSERT_TRUE(tick(stem, scratch, frame_scratch));
        const double now = stem_energy(stem.points, stem.rest, stem.springs, nullptr, no_gravity, &stem.frame).total();
        ASSERT_LE(now, previous * (1.0 + 1e-9) + 1e-15) << "tick " << t;
        previous = now;
    }
    EXPECT_LT(previous, start);
}

// The directions of a rest shape read back as the shape they were taken from: laid as an arc, taken as
// its rest bends, the stem's forces are nothing but its weight's.
TEST(StemFrame, AShapeTakenAsItsRestShapeIsAtRest) {
    StemSpec spec = willow_spec();
    spec.rest_bend_rad = 50 * deg;
    spec.bend_towards = {0, 1, 0};
    BuiltStem stem = build_stem(spec);
    rest_bends_from_shape(stem.points.position_m, stem.frame, stem.rest);
    std::vector<glm::dvec3> f;
    stem_forces(stem.points, stem.rest, stem.springs, nullptr, no_gravity, f, &stem.frame);
    for (std::size_t p = 0; p < f.size(); ++p) EXPECT_LT(glm::length(f[p]), 1e-9) << "point " << p;
    for (double angle : stem.rest.hinge_angle_rad) EXPECT_NEAR(angle, 50 * deg / 19, 1e-12);
}

// Leaves and petals sit on the bark: turn the stem's frame a quarter turn about an upright stem and a
// part's place turns a quarter turn with it. An untwisted frame built with the stem places them where
// they were placed before stems had one (the room's x across the stem at its bottom).
TEST(StemFrame, PartsTurnWithTheBark) {
    BuiltStem stem = build_stem(willow_spec());
    const auto& x = stem.points.position_m;
    const glm::dvec3 offset{0.02, 0.0, 0.0};
    const auto before = attachment_frame(x, 10, stem.frame.director);
    const auto plain = attachment_frame(x, 10);
    EXPECT_NEAR(glm::length(before.place(offset) - plain.place(offset)), 0.0, 1e-12) << "untwisted: as without a frame";
    std::vector<glm::dvec3> turned = stem.frame.director;
    for (auto& d : turned) d = glm::cross(glm::dvec3{0, 0, 1}, d); // a quarter turn about the upright stem
    const auto after = attachment_frame(x, 10, turned);
    const glm::dvec3 was = before.place(offset) - x[10], now = after.place(offset) - x[10];
    EXPECT_NEAR(glm::dot(was, now), 0.0, 1e-12);
    EXPECT_NEAR(glm::cross(was, now).z, 0.02 * 0.02, 1e-12) << "turned the bark's way";
}

// A frame nothing turns is carried once every few ticks, in one go, and comes out where turning it every
// tick would have; a hold that turns it is taken the tick it comes.
TEST(StemFrame, AQuietFrameFollowsItsStemAndAHoldThatTurnsItWakesIt) {
    BuiltStem stem = build_stem(willow_spec());
    FrameScratch scratch;
    const glm::dvec3 start = stem.frame.director[5];
    // The whole stem swung about the room's x axis, a milliradian a tick, for 16 ticks.
    const double step = 1e-3;
    const auto swing = [&](glm::dvec3 v, double angle) { return glm::dvec3{v.x, std::cos(angle) * v.y - std::sin(angle) * v.z, std::sin(angle) * v.y + std::cos(angle) * v.z}; };
    const auto laid = stem.points.position_m;
    update_frame(stem.frame, stem.points.position_m, stem.rest, stem.springs.hinge_nm_per_rad, scratch); // relaxes
    for (int t = 1; t <= 2 * quiet_carry_ticks; ++t) {
        for (std::size_t p = 0; p < laid.size(); ++p) stem.points.position_m[p] = swing(laid[p], step * t);
        update_frame(stem.frame, stem.points.position_m, stem.rest, stem.springs.hinge_nm_per_rad, scratch);
    }
    EXPECT_NEAR(glm::length(stem.frame.director[5] - swing(start, step * 2 * quiet_carry_ticks)), 0.0, 1e-9);
    // A grip takes segment 5 turned 30 degrees about it: set at once, not a few ticks later.
    const glm::dvec3 e = glm::normalize(stem.points.position_m[6] - stem.points.position_m[5]);
    const glm::dvec3 d = stem.frame.director[5];
    const glm::dvec3 held = std::cos(0.5236) * d + std::sin(0.5236) * glm::cross(e, d);
    stem.frame.held[5] = 1;
    stem.frame.held_director[5] = held;
    update_frame(stem.frame, stem.points.position_m, stem.rest, stem.springs.hinge_nm_per_rad, scratch);
    EXPECT_NEAR(glm::length(stem.frame.director[5] - held), 0.0, 1e-9);
}
