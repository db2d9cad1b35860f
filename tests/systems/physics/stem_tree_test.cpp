#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "systems/physics/stem_builder.hpp"
#include "systems/physics/stem_dynamics.hpp"
#include "systems/physics/stem_frame.hpp"
#include "systems/physics/stem_tree.hpp"

using namespace ikebana;
using namespace ikebana::systems::physics;

namespace {
constexpr double dt = 1e-3;
constexpr double pi = 3.14159265358979323846;
constexpr double deg = pi / 180.0;
const glm::dvec3 gravity{0.0, 0.0, -9.81};

StemSpec branch_spec() {
    StemSpec s; // a cherry-like branch: 300 mm of 6 mm, E 2 GPa
    s.segments = 12;
    s.length_m = 0.30;
    s.diameter_m = 0.006;
    s.youngs_modulus_pa = 2.0e9;
    s.stem_mass_kg = 0.008;
    return s;
}

StemSpec twig_spec() {
    StemSpec s;
    s.segments = 8;
    s.length_m = 0.12;
    s.diameter_m = 0.0025;
    s.youngs_modulus_pa = 2.0e9;
    s.stem_mass_kg = 0.0015;
    return s;
}

// The fork direction (in the parent's frame at `at_point - 1`) whose rotation axis is `axis` in the room.
glm::dvec2 direction_for(const BuiltStem& parent, std::uint32_t at_point, glm::dvec3 axis) {
    const auto& x = parent.points.position_m;
    const glm::dvec3 e = glm::normalize(x[at_point] - x[at_point - 1]);
    const glm::dvec3 d1 = parent.frame.director[at_point - 1];
    return {glm::dot(axis, d1), glm::dot(axis, glm::cross(e, d1))};
}

struct Forked {
    BuiltStem stem;
    BuiltTwig twig;
    components::StemClamp clamp{};
    std::vector<TreeChain> chains() {
        return {TreeChain{&stem.points, &stem.rest, &stem.springs, clamp.engaged ? &clamp : nullptr, &stem.frame, -1, nullptr},
                TreeChain{&twig.stem.points, &twig.stem.rest, &twig.stem.springs, nullptr, &twig.stem.frame, 0, &twig.fork}};
    }
};

glm::dvec3 momentum(const components::StemPoints& p) {
    glm::dvec3 sum{0.0};
    for (std::size_t i = 0; i < p.position_m.size(); ++i) sum += p.mass_kg[i] * p.velocity_m_s[i];
    return sum;
}
} // namespace

// The tree's solve is the chain's banded one with another elimination order: for a stem without twigs
// both give the same steps (to rounding), clamped, leaning, under gravity, over half a second.
TEST(StemTree, OneChainStepsAsTheBandedSolverDoes) {
    StemSpec spec = branch_spec();
    spec.direction = glm::normalize(glm::dvec3{0.4, 0.1, 1.0});
    spec.youngs_modulus_pa = 3.0e8;
    BuiltStem banded = build_stem(spec);
    BuiltStem tree = build_stem(spec);
    const auto clamp = clamp_bottom(banded);
    banded.points.velocity_m_s[7] = tree.points.velocity_m_s[7] = glm::dvec3{0.3, -0.2, 0.1};
    StemSolverScratch band_scratch;
    TreeScratch tree_scratch;
    for (int t = 0; t < 500; ++t) {
        ASSERT_TRUE(step_stem(banded.points, banded.rest, banded.springs, &clamp, gravity, dt, band_scratch, &banded.frame));
        const TreeChain chain{&tree.points, &tree.rest, &tree.springs, &clamp, &tree.frame, -1, nullptr};
        ASSERT_TRUE(step_tree(std::span(&chain, 1), gravity, dt, tree_scratch, true));
    }
    const double sag = glm::length(banded.points.position_m.back() - build_stem(spec).points.position_m.back());
    ASSERT_GT(sag, 1e-3) << "the stem moved: the comparison means something";
    for (std::size_t i = 0; i < banded.points.position_m.size(); ++i) {
        EXPECT_NEAR(glm::length(banded.points.position_m[i] - tree.points.position_m[i]), 0.0, 1e-9) << "point " << i;
    }
}

// One body: with no gravity, no drag and nothing holding it, a forked branch set moving with different
// velocities at every point keeps its momentum exactly (the stem's and the twig's forces on their shared
// point are one point's), and its twig stays on it.
TEST(StemTree, AForkedBranchIsOneBodyAndKeepsItsMomentum) {
    StemSpec spec = branch_spec();
    spec.air_drag_per_s = 0.0;
    Forked f{build_stem(spec), {}, {}};
    StemSpec ts = twig_spec();
    ts.air_drag_per_s = 0.0;
    f.twig = build_twig(ts, f.stem.points, f.stem.frame, 6, 40.0 * deg, {1.0, 0.0});
    for (std::size_t i = 0; i < f.stem.points.position_m.size(); ++i) {
        const double u = static_cast<double>(i);
        f.stem.points.velocity_m_s[i] = glm::dvec3{0.1 * std::sin(u), 0.05 * std::cos(2.0 * u), 0.02 * u};
    }
    for (std::size_t i = 1; i < f.twig.stem.points.position_m.size(); ++i) f.twig.stem.points.velocity_m_s[i] = glm::dvec3{-0.2, 0.1 * std::sin(3.0 * static_cast<double>(i)), 0.0};
    f.twig.stem.points.velocity_m_s[0] = f.stem.points.velocity_m_s[6];
    const glm::dvec3 before = momentum(f.stem.points) + momentum(f.twig.stem.points);
    TreeScratch scratch;
    for (int t = 0; t < 300; ++t) {
        auto chains = f.chains();
        ASSERT_TRUE(step_tree(chains, glm::dvec3{0.0}, dt, scratch, false));
    }
    const glm::dvec3 after = momentum(f.stem.points) + momentum(f.twig.stem.points);
    EXPECT_NEAR(glm::length(after - before), 0.0, 1e-11 + 1e-9 * glm::length(before));
    EXPECT_EQ(f.twig.stem.points.position_m[0], f.stem.points.position_m[6]);
    // The fork keeps its angle (within what the motion flexes it).
    const auto& x = f.stem.points.position_m;
    const auto& y = f.twig.stem.points.position_m;
    const double fork = std::acos(glm::dot(glm::normalize(x[6] - x[5]), glm::normalize(y[1] - y[0])));
    EXPECT_NEAR(fork, 40.0 * deg, 8.0 * deg);
}

// Energy never grows without input: a forked branch bent out of its rest shape and let go, clamped,
// without gravity, loses energy every step.
TEST(StemTree, AForkedBranchLetGoNeverGainsEnergy) {
    Forked f{build_stem(branch_spec()), {}, {}};
    f.clamp = clamp_bottom(f.stem);
    f.twig = build_twig(twig_spec(), f.stem.points, f.stem.frame, 8, 50.0 * deg, {0.0, 1.0});
    // Pushed: the stem's top and the twig's tip moved sideways (a deformed pose, at rest).
    for (std::size_t i = 1; i < f.stem.points.position_m.size(); ++i) f.stem.points.position_m[i].x += 0.002 * static_cast<double>(i * i) / 12.0;
    for (std::size_t i = 1; i < f.twig.stem.points.position_m.size(); ++i) f.twig.stem.points.position_m[i] += glm::dvec3{0.0, 0.003 * static_cast<double>(i), 0.0} + (f.stem.points.position_m[8] - f.twig.stem.points.position_m[0]);
    f.twig.stem.points.position_m[0] = f.stem.points.position_m[8];
    TreeScratch scratch;
    auto chains = f.chains();
    double energy = tree_energy(chains, glm::dvec3{0.0}).total();
    const double start = energy;
    ASSERT_GT(start, 1e-5);
    for (int t = 0; t < 1000; ++t) {
        chains = f.chains();
        ASSERT_TRUE(step_tree(chains, glm::dvec3{0.0}, dt, scratch, false));
        const double now = tree_energy(chains, glm::dvec3{0.0}).total();
        ASSERT_LE(now, energy + 1e-9 * start) << "step " << t;
        energy = now;
    }
    EXPECT_LT(energy, 0.2 * start) << "and it settles";
}

// The twig's weight loads its stem as beam theory says: a horizontal branch clamped at one end, with a
// twig hanging straight down from its tip, sags as the same branch with the twig's mass hung at its tip
// as a point load (P L^3 / 3 E I more than its own weight's w L^4 / 8 E I).
TEST(StemTree, ATwigsWeightBendsItsStemAsAPointLoadAtTheFork) {
    StemSpec spec = branch_spec();
    spec.direction = glm::dvec3{1.0, 0.0, 0.0};
    spec.youngs_modulus_pa = 5.0e8;
    Forked f{build_stem(spec), {}, {}};
    f.clamp = clamp_bottom(f.stem);
    const std::uint32_t tip = spec.segments;
    f.twig = build_twig(twig_spec(), f.stem.points, f.stem.frame, tip, 90.0 * deg, direction_for(f.stem, tip, {0.0, 1.0, 0.0}));
    ASSERT_NEAR(glm::normalize(f.twig.stem.points.position_m.back() - f.twig.stem.points.position_m[0]).z, -1.0, 1e-9) << "the twig hangs down";
    // The same branch, the twig's mass at its tip.
    BuiltStem loaded = build_stem(spec);
    double twig_mass = 0.0;
    for (const double m : f.twig.stem.points.mass_kg) twig_mass += m;
    loaded.points.mass_kg.back() += twig_mass;
    const auto clamp = clamp_bottom(loaded);
    TreeScratch scratch;
    StemSolverScratch band;
    for (int t = 0; t < 3000; ++t) {
        auto chains = f.chains();
        ASSERT_TRUE(step_tree(chains, gravity, dt, scratch, false));
        ASSERT_TRUE(step_stem(loaded.points, loaded.rest, loaded.springs, &clamp, gravity, dt, band, &loaded.frame));
    }
    const double forked_sag = -f.stem.points.position_m.back().z;
    const double point_sag = -loaded.points.position_m.back().z;
    const double ei = spec.youngs_modulus_pa * second_moment_of_area(spec.diameter_m);
    const double l = spec.length_m;
    const double theory = twig_mass * 9.81 * l * l * l / (3.0 * ei) + spec.stem_mass_kg / l * 9.81 * l * l * l * l / (8.0 * ei);
    ASSERT_GT(point_sag, 0.01);
    EXPECT_NEAR(forked_sag, point_sag, 0.03 * point_sag);
    EXPECT_NEAR(point_sag, theory, 0.05 * theory);
}

// The fork's side is in the stem's frame: twist the stem a quarter turn (its directors turned about its
// segments, as a hand turning the branch leaves them) and the twig swings a quarter turn about it.
TEST(StemTree, ATwigTurnsWithItsStemWhenTheStemIsTurned) {
    Forked f{build_stem(branch_spec()), {}, {}};
    f.clamp = clamp_bottom(f.stem);
    f.twig = build_twig(twig_spec(), f.stem.points, f.stem.frame, 8, 60.0 * deg, {1.0, 0.0});
    const auto side = [&] {
        const glm::dvec3 out = f.twig.stem.points.position_m[1] - f.twig.stem.points.position_m[0];
        return std::atan2(out.y, out.x);
    };
    const double before = side();
    for (std::size_t s = 0; s < f.stem.frame.director.size(); ++s) {
        const glm::dvec3 e = glm::normalize(f.stem.points.position_m[s + 1] - f.stem.points.position_m[s]);
        f.stem.frame.director[s] = glm::cross(e, f.stem.frame.director[s]); // a quarter turn about e
    }
    TreeScratch scratch;
    for (int t = 0; t < 1500; ++t) {
        auto chains = f.chains();
        ASSERT_TRUE(step_tree(chains, glm::dvec3{0.0}, dt, scratch, false));
    }
    double turned = side() - before;
    while (turned > pi) turned -= 2.0 * pi;
    while (turned < -pi) turned += 2.0 * pi;
    EXPECT_NEAR(turned, 90.0 * deg, 3.0 * deg);
}

// A twig held by a hand (a pinned point) holds the branch up through the fork; the held point stays.
TEST(StemTree, AHeldTwigHoldsItsBranch) {
    Forked f{build_stem(branch_spec()), {}, {}};
    f.twig = build_twig(twig_spec(), f.stem.points, f.stem.frame, 9, 45.0 * deg, {1.0, 0.0});
    const std::size_t held = 4;
    f.twig.stem.points.pinned[held] = 1;
    const glm::dvec3 at = f.twig.stem.points.position_m[held];
    TreeScratch scratch;
    for (int t = 0; t < 2000; ++t) {
        auto chains = f.chains();
        ASSERT_TRUE(step_tree(chains, gravity, dt, scratch, true));
    }
    EXPECT_EQ(f.twig.stem.points.position_m[held], at);
    // It hangs below the hand, still: the hand carries the whole branch's weight.
    double mass = 0.0;
    for (const double m : f.stem.points.mass_kg) mass += m;
    for (const double m : f.twig.stem.points.mass_kg) mass += m;
    EXPECT_LT(f.stem.points.position_m.front().z, at.z);
    EXPECT_LT(glm::length(f.stem.points.velocity_m_s.front()), 0.05);
    // The load on the held point is what the hand feels: the branch's weight, once it has stopped.
    EXPECT_NEAR(-scratch.load[1][held].z, mass * 9.81, 0.05 * mass * 9.81);
}
