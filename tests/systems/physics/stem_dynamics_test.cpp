#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "systems/physics/stem_builder.hpp"
#include "systems/physics/stem_dynamics.hpp"

using namespace ikebana;
using namespace ikebana::systems::physics;

namespace {
constexpr double dt = 1e-3; // the haptic rate the stem must be stable at
const glm::dvec3 no_gravity{0.0};
const glm::dvec3 earth{0.0, 0.0, -9.80665};

StemSpec sunflower_spec() {
    StemSpec s; // 230 mm, 7.5 mm: the paper's sunflower
    s.segments = 20;
    s.length_m = 0.230;
    s.diameter_m = 0.0075;
    s.youngs_modulus_pa = 3.0e8; // fresh herbaceous stem; at 5e7 the head would exceed the buckling load
    s.stem_mass_kg = 0.008;
    s.head_mass_kg = 0.05;
    return s;
}

StemSpec branch_spec() {
    StemSpec s; // a green woody branch: stiff, thin
    s.segments = 24;
    s.length_m = 0.35;
    s.diameter_m = 0.006;
    s.youngs_modulus_pa = 6.0e9;
    s.stem_mass_kg = 0.009;
    return s;
}

void run(BuiltStem& stem, const components::StemClamp* clamp, glm::dvec3 g, int ticks, StemSolverScratch& scratch) {
    for (int t = 0; t < ticks; ++t) ASSERT_TRUE(step_stem(stem.points, stem.rest, stem.springs, clamp, g, dt, scratch));
}

glm::dvec3 momentum(const BuiltStem& stem) {
    glm::dvec3 p{0.0};
    for (std::size_t i = 0; i < stem.points.mass_kg.size(); ++i) p += stem.points.mass_kg[i] * stem.points.velocity_m_s[i];
    return p;
}
} // namespace

// Euler-Bernoulli: a cantilever of length L under a tip load P deflects P L^3 / (3 E I).
TEST(StemDynamics, CantileverTipDeflectionMatchesEulerBernoulli) {
    for (const auto& spec0 : {sunflower_spec(), branch_spec()}) {
        StemSpec spec = spec0;
        spec.direction = {1.0, 0.0, 0.0}; // horizontal
        spec.head_mass_kg = 0.0;
        spec.air_drag_per_s = 5.0; // settle quickly; the equilibrium does not depend on damping
        BuiltStem stem = build_stem(spec);
        const auto clamp = clamp_bottom(stem);
        const double ei = stem.bending_stiffness_nm2;
        const double l = spec.length_m;
        // A load giving about 1 % of L deflection keeps us in the linear theory's range.
        const double load = 0.01 * l * 3.0 * ei / (l * l * l);
        StemSolverScratch scratch;
        const std::size_t tip = stem.points.position_m.size() - 1;
        for (int t = 0; t < 8000; ++t) {
            stem.points.external_force_n[tip] = {0.0, 0.0, -load};
            ASSERT_TRUE(step_stem(stem.points, stem.rest, stem.springs, &clamp, no_gravity, dt, scratch));
        }
        const double deflection = -stem.points.position_m[tip].z;
        const double expected = load * l * l * l / (3.0 * ei);
        EXPECT_NEAR(deflection, expected, 0.05 * expected) << "E = " << spec.youngs_modulus_pa;
        // The tip has come to rest there.
        EXPECT_LT(glm::length(stem.points.velocity_m_s[tip]), 1e-4 * l);
    }
}

TEST(StemDynamics, BentHingeReturnsToItsRestAngle) {
    StemSpec spec = sunflower_spec();
    spec.segments = 8;
    spec.rest_bend_rad = 0.35; // a naturally curved stem
    spec.head_mass_kg = 0.0;
    BuiltStem stem = build_stem(spec);
    // Bend it further by pushing the middle sideways.
    stem.points.position_m[4] += glm::dvec3{0.01, 0.005, 0.0};
    StemSolverScratch scratch;
    run(stem, nullptr, no_gravity, 5000, scratch);
    for (std::size_t i = 1; i + 1 < stem.points.position_m.size(); ++i) {
        EXPECT_NEAR(hinge_angle(stem.points, i), stem.rest.hinge_angle_rad[i - 1], 1e-3) << "hinge " << i;
    }
}

TEST(StemDynamics, MomentumIsConservedWithoutGravityOrContacts) {
    StemSpec spec = sunflower_spec();
    spec.air_drag_per_s = 0.0; // drag acts on absolute velocity; spring damping on relative only
    BuiltStem stem = build_stem(spec);
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (auto& v : stem.points.velocity_m_s) v = {u(rng), u(rng), u(rng)};
    for (auto& x : stem.points.position_m) x += 0.002 * glm::dvec3{u(rng), u(rng), u(rng)};
    const glm::dvec3 before = momentum(stem);
    StemSolverScratch scratch;
    run(stem, nullptr, no_gravity, 2000, scratch);
    const glm::dvec3 after = momentum(stem);
    double total_mass = 0.0;
    for (double m : stem.points.mass_kg) total_mass += m;
    EXPECT_NEAR(glm::length(after - before), 0.0, 1e-9 * total_mass);
}

TEST(StemDynamics, EnergyNeverGrowsWithoutInput) {
    for (const auto& spec0 : {sunflower_spec(), branch_spec()}) {
        StemSpec spec = spec0;
        spec.air_drag_per_s = 0.0;
        BuiltStem stem = build_stem(spec);
        const auto clamp = clamp_bottom(stem);
        // Pluck it: a sideways displacement of the upper half, released from rest.
        for (std::size_t i = stem.points.position_m.size() / 2; i < stem.points.position_m.size(); ++i) {
            stem.points.position_m[i].x += 0.02 * static_cast<double>(i) / static_cast<double>(stem.points.position_m.size());
        }
        StemSolverScratch scratch;
        double previous = stem_energy(stem.points, stem.rest, stem.springs, &clamp, earth).total();
        const double scale = std::abs(previous) + 1e-3;
        double worst_rise = 0.0;
        for (int t = 0; t < 3000; ++t) {
            ASSERT_TRUE(step_stem(stem.points, stem.rest, stem.springs, &clamp, earth, dt, scratch));
            const double e = stem_energy(stem.points, stem.rest, stem.springs, &clamp, earth).total();
            worst_rise = std::max(worst_rise, e - previous);
            previous = e;
        }
        EXPECT_LE(worst_rise, 1e-6 * scale) << "E = " << spec.youngs_modulus_pa;
    }
}

TEST(StemDynamics, ReleasedStemSettles) {
    StemSpec spec = sunflower_spec();
    BuiltStem stem = build_stem(spec);
    const auto clamp = clamp_bottom(stem);
    for (auto& x : stem.points.position_m) x.y += 0.1 * x.z; // tilted 6 degrees against its clamp
    StemSolverScratch scratch;
    run(stem, &clamp, earth, 10000, scratch);
    const auto energy = stem_energy(stem.points, stem.rest, stem.springs, &clamp, earth);
    EXPECT_LT(energy.kinetic_j, 1e-9);
    double fastest = 0.0;
    for (const auto& v : stem.points.velocity_m_s) fastest = std::max(fastest, glm::length(v));
    EXPECT_LT(fastest, 1e-4) << "m/s";
}

// The largest force a hand can apply, at random points and directions, changing every 10 ms, for
// 10^6 ticks: no NaN, nothing flies off.
TEST(StemDynamics, RandomBoundedInputNeverProducesNaN) {
    for (const auto& spec0 : {sunflower_spec(), branch_spec()}) {
        StemSpec spec = spec0;
        spec.segments = 10;
        BuiltStem stem = build_stem(spec);
        const auto clamp = clamp_bottom(stem);
        StemSolverScratch scratch;
        std::mt19937_64 rng(5);
        std::uniform_real_distribution<double> u(-1.0, 1.0);
        std::uniform_int_distribution<std::size_t> pick(1, stem.points.position_m.size() - 1);
        constexpr double max_hand_force_n = 40.0;
        std::size_t point = 1;
        glm::dvec3 force{0.0};
        double farthest = 0.0;
        for (int t = 0; t < 1'000'000; ++t) {
            if (t % 10 == 0) {
                point = pick(rng);
                force = max_hand_force_n * glm::dvec3{u(rng), u(rng), u(rng)} / std::sqrt(3.0);
            }
            stem.points.external_force_n[point] = force;
            ASSERT_TRUE(step_stem(stem.points, stem.rest, stem.springs, &clamp, earth, dt, scratch)) << "tick " << t;
            for (auto& f : stem.points.external_force_n) f = glm::dvec3{0.0};
            if (t % 1000 == 0) {
                for (const auto& x : stem.points.position_m) {
                    ASSERT_TRUE(std::isfinite(x.x) && std::isfinite(x.y) && std::isfinite(x.z)) << "tick " << t;
                    farthest = std::max(farthest, glm::length(x));
                }
            }
        }
        // Clamped at the origin, a stem can reach no farther than its own (slightly stretched) length.
        EXPECT_LT(farthest, 1.5 * spec.length_m);
    }
}

// The paper's 1 ms is one step for any stem, however stiff and however many segments: the shipped
// cherry branch (8 mm, fastest hinge mode about 55,000 rad/s, omega dt 55; its tick was once cut in
// three) with its natural curve, clamped at 45 degrees, and an 80-segment sunflower at 30 degrees
// (omega dt 16 times its 20-segment one's), each knocked at its top, step once a tick for 3 s: their
// energy never grows, and the knock dies away. A longer tick is cut into 1 ms parts, 8 at most.
TEST(StemDynamics, AStiffCurvedBranchAndAnEightySegmentStemTakeOneStepATickAndNeverGainEnergy) {
    StemSpec cherry = branch_spec();
    cherry.diameter_m = 0.008;
    cherry.rest_bend_rad = 20.0 * M_PI / 180.0;
    cherry.bend_towards = {0.0, 1.0, 0.0};
    cherry.direction = glm::normalize(glm::dvec3{1.0, 0.0, 1.0});
    cherry.stiffness_damping_s = 0.002;
    StemSpec long_sunflower = sunflower_spec();
    long_sunflower.segments = 80;
    long_sunflower.direction = glm::normalize(glm::dvec3{0.5, 0.0, std::sqrt(3.0) / 2.0});
    for (const StemSpec& spec : {cherry, long_sunflower}) {
        BuiltStem stem = build_stem(spec);
        const auto clamp = clamp_bottom(stem);
        stem.points.velocity_m_s.back() = {0.0, 1.0, 0.0}; // a knock
        const double knock_j = 0.5 * stem.points.mass_kg.back();
        const auto total = [&] {
            const StemEnergy e = stem_energy(stem.points, stem.rest, stem.springs, &clamp, earth, &stem.frame);
            return e.kinetic_j + e.elastic_j + e.gravitational_j;
        };
        StemSolverScratch scratch;
        double before = total();
        const double start = before;
        double most_gained = 0.0;
        for (int t = 0; t < 3000; ++t) {
            ASSERT_TRUE(step_stem(stem.points, stem.rest, stem.springs, &clamp, earth, dt, scratch, &stem.frame)) << spec.segments << " tick " << t;
            const double now = total();
            most_gained = std::max(most_gained, now - before);
            before = now;
        }
        EXPECT_LT(most_gained, 1e-9 * std::abs(start) + 1e-12) << spec.segments << " segments: energy grew in a tick";
        const StemEnergy end = stem_energy(stem.points, stem.rest, stem.springs, &clamp, earth, &stem.frame);
        EXPECT_LT(end.kinetic_j, 0.01 * knock_j) << spec.segments << " segments: the knock dies away (under 1 % of it left after 3 s)";
    }
    EXPECT_EQ(tick_parts(dt), 1u);
    EXPECT_EQ(tick_parts(dt / 2), 1u);
    EXPECT_EQ(tick_parts(4 * dt), 4u);
    EXPECT_EQ(tick_parts(1.0), max_substeps) << "a 1 Hz tick: eight parts";
}

// Stems stepped together (their solves four at a time, in the lanes of one register) land exactly
// where each stepped alone lands, bit for bit: five stems of three lengths (a group of four and one
// alone), clamped and free, one held at a point, one with a curved rest shape, two stepping a third of
// the others' step, for 300 ticks. And a
// stem whose step fails is refused alone: its neighbours in the register step on.
TEST(StemDynamics, StemsSteppedSideBySideLandWhereEachSteppedAloneLands) {
    std::vector<BuiltStem> together;
    for (int k = 0; k < 5; ++k) {
        StemSpec spec = k % 2 ? branch_spec() : sunflower_spec();
        spec.segments = 12 + 7 * static_cast<std::uint32_t>(k % 3);
        spec.direction = glm::normalize(glm::dvec3{0.3 * k, 0.1, 1.0});
        spec.rest_bend_rad = k == 3 ? 0.4 : 0.0;
        together.push_back(build_stem(spec));
    }
    together[2].points.pinned.back() = 1; // a hand holds its top
    std::vector<BuiltStem> alone = together;
    const glm::dvec3 top_before = together[4].points.position_m.back();
    std::vector<components::StemClamp> clamps;
    for (const auto& s : together) clamps.push_back(clamp_bottom(s));
    clamps[4].engaged = false; // one free stem
    std::vector<StemSolverScratch> scratch(5);
    std::vector<StemSolverScratch> alone_scratch(5);
    LaneScratch lanes;
    std::vector<std::uint8_t> ok(5, 0);
    for (int t = 0; t < 300; ++t) {
        std::vector<StemStep> steps;
        // Stems of different steps share the register (a stiff stem's part beside a whole tick).
        const auto dt_of = [](std::size_t k) { return k % 2 ? dt / 3.0 : dt; };
        for (std::size_t k = 0; k < 5; ++k) steps.push_back({&together[k].points, &together[k].rest, &together[k].springs, &clamps[k], &scratch[k], dt_of(k)});
        step_stems(steps, earth, lanes, ok);
        for (std::size_t k = 0; k < 5; ++k) {
            ASSERT_EQ(ok[k], 1u) << "stem " << k << " tick " << t;
            ASSERT_TRUE(step_stem(alone[k].points, alone[k].rest, alone[k].springs, &clamps[k], earth, dt_of(k), alone_scratch[k]));
        }
    }
    for (std::size_t k = 0; k < 5; ++k) {
        for (std::size_t p = 0; p < together[k].points.position_m.size(); ++p) {
            ASSERT_EQ(together[k].points.position_m[p], alone[k].points.position_m[p]) << "stem " << k << " point " << p;
            ASSERT_EQ(together[k].points.velocity_m_s[p], alone[k].points.velocity_m_s[p]) << "stem " << k << " point " << p;
        }
        EXPECT_EQ(scratch[k].end_force, alone_scratch[k].end_force) << "stem " << k;
    }
    EXPECT_GT(glm::length(together[4].points.position_m.back() - top_before), 0.05) << "the free stem fell: they did move";

    // A stem with a zero mass point cannot be solved (its system is not positive definite once a
    // spring is gone): refused, while the three beside it step.
    together[1].points.mass_kg[3] = 0.0;
    together[1].springs.axial_n_per_m[2] = 0.0;
    together[1].springs.axial_n_per_m[3] = 0.0;
    together[1].springs.hinge_nm_per_rad.assign(together[1].springs.hinge_nm_per_rad.size(), 0.0);
    std::vector<StemStep> steps;
    for (std::size_t k = 0; k < 4; ++k) steps.push_back({&together[k].points, &together[k].rest, &together[k].springs, &clamps[k], &scratch[k], dt});
    StemSolverScratch single;
    auto copy = together[1];
    const bool alone_ok = step_stem(copy.points, copy.rest, copy.springs, &clamps[1], earth, dt, single);
    step_stems(steps, earth, lanes, ok);
    EXPECT_FALSE(alone_ok);
    EXPECT_EQ(ok[1], 0u);
    EXPECT_EQ(ok[0], 1u);
    EXPECT_EQ(ok[2], 1u);
    EXPECT_EQ(ok[3], 1u);
}

// The hinge angle of a nearly straight hinge comes from a series, not atan2 (5x cheaper): over bends
// from 1e-9 rad to 10 degrees and beyond, in every direction, it equals the library's atan2 of the same
// vectors to within 2 units in the last place.
TEST(StemDynamics, ANearlyStraightHingesAngleIsTheLibrarysToTheLastBits) {
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    int series = 0;
    for (int k = 0; k < 20000; ++k) {
        const double theta = std::pow(10.0, -9.0 + 9.5 * unit(rng)); // up to about 3 rad
        const double phi = 6.283185307179586 * unit(rng);
        components::StemPoints pts;
        const glm::dvec3 in = glm::normalize(glm::dvec3{unit(rng) - 0.5, unit(rng) - 0.5, 1.0});
        const glm::dvec3 side = glm::normalize(glm::cross(in, glm::dvec3{std::cos(phi), std::sin(phi), 0.3}));
        const glm::dvec3 out = std::cos(theta) * in + std::sin(theta) * side;
        pts.position_m = {glm::dvec3{0.01, 0.02, 0.0}, glm::dvec3{0.01, 0.02, 0.0} + 0.012 * in, glm::dvec3{0.01, 0.02, 0.0} + 0.012 * in + 0.0115 * out};
        const glm::dvec3 a = glm::normalize(pts.position_m[1] - pts.position_m[0]);
        const glm::dvec3 b = glm::normalize(pts.position_m[2] - pts.position_m[1]);
        const double reference = std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
        const double angle = hinge_angle(pts, 1);
        ASSERT_NEAR(angle, reference, 2.0 * std::numeric_limits<double>::epsilon() * reference + 1e-300) << "theta " << theta;
        series += theta < 0.12 ? 1 : 0;
    }
    EXPECT_GT(series, 15000) << "most of them small enough for the series";
}

// A stem carried by a point held at constant speed (as the grab moves a held point: its position
// moved and its velocity set each tick) moves along with it: the stiffness damping acts on the stem's
// motion relative to the hand, not against the hand's own. Weightless and without air drag, after a
// second every point moves at the hand's speed (solving for the new velocity once dropped the held
// point's share of the damping: the points lagged by 2.5e-4 m/s and the grip's end force was 995 N
// instead of the 18 N the change-of-velocity form gives).
TEST(StemDynamics, AStemCarriedAtConstantSpeedMovesWithTheHand) {
    StemSpec spec = sunflower_spec();
    spec.head_mass_kg = 0.0;
    spec.air_drag_per_s = 0.0;
    BuiltStem stem = build_stem(spec);
    const std::size_t held = stem.points.position_m.size() / 2;
    stem.points.pinned[held] = 1;
    const glm::dvec3 speed{0.1, 0.0, 0.0};
    StemSolverScratch scratch;
    for (int t = 0; t < 1000; ++t) {
        stem.points.position_m[held] += speed * dt;
        stem.points.velocity_m_s[held] = speed;
        ASSERT_TRUE(step_stem(stem.points, stem.rest, stem.springs, nullptr, no_gravity, dt, scratch));
    }
    for (std::size_t p = 0; p < stem.points.position_m.size(); ++p) {
        if (p == held) continue;
        EXPECT_NEAR(stem.points.velocity_m_s[p].x, speed.x, 1e-8) << "point " << p;
    }
    EXPECT_LT(glm::length(scratch.end_force[held]), 50.0);
}

// A stem refused for one tick (a non-finite force on it) in a group of stems stepped side by side is
// stepped again the next tick, as it would be alone: its lane's rows are rebuilt, not left with NaN.
TEST(StemDynamics, AStemRefusedOnceInItsGroupStepsAgainTheNextTick) {
    std::vector<BuiltStem> stems;
    for (std::uint32_t segments : {20u, 12u, 20u}) {
        StemSpec spec = sunflower_spec();
        spec.segments = segments;
        stems.push_back(build_stem(spec));
    }
    std::vector<components::StemClamp> clamps;
    for (const auto& s : stems) clamps.push_back(clamp_bottom(s));
    std::vector<StemSolverScratch> scratch(3);
    LaneScratch lanes;
    std::vector<std::uint8_t> ok(3, 0);
    auto step = [&] {
        std::vector<StemStep> steps;
        for (std::size_t k = 0; k < 3; ++k) steps.push_back({&stems[k].points, &stems[k].rest, &stems[k].springs, &clamps[k], &scratch[k], dt});
        step_stems(steps, earth, lanes, ok);
    };
    step();
    stems[1].points.external_force_n[5] = glm::dvec3{std::numeric_limits<double>::quiet_NaN()};
    step();
    EXPECT_EQ(ok[1], 0u) << "refused";
    EXPECT_EQ(ok[0], 1u);
    for (auto& v : stems[1].points.velocity_m_s) v = glm::dvec3{0.0}; // as the physics system leaves it
    stems[1].points.external_force_n[5] = glm::dvec3{0.0};
    for (int t = 0; t < 3; ++t) {
        step();
        EXPECT_EQ(ok[1], 1u) << "tick " << t << " after";
    }
}
