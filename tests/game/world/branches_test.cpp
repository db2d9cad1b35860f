// Forked branches in the world: the species' twigs made, carried with their stem, moved by a cut,
// pruned off at the hand (falling to the table), a leaf stripped; and the species file's branch fields.
#include <gtest/gtest.h>

#include <cmath>
#include <numeric>
#include <sstream>

#include "components/collision.hpp"
#include "components/flower.hpp"
#include "components/insertion.hpp"
#include "components/stem.hpp"
#include "engine/devices/scripted_device.hpp"
#include "engine/ecs/hierarchy.hpp"
#include "engine/sched/clocks.hpp"
#include "game/species/species.hpp"
#include "game/world/world.hpp"
#include "systems/insertion/stem_cutting_system.hpp"
#include "systems/physics/part_attachment.hpp"
#include "systems/presentation/frame_channel.hpp"
#include "../haptics/scripted_hands.hpp"

using namespace ikebana;
using namespace ikebana::game;
using namespace ikebana::components;

namespace {

// A branch standing in the kenzan and one hand, whose device holds it (button up) where `at` says.
struct Bench {
    std::unique_ptr<World> w;
    std::unique_ptr<sched::DeterministicClock> clock;
    ecs::Entity flower() const { return w->flowers[0].entity; }
    const std::vector<ecs::Entity>& twigs() const { return w->sim.get<Twigs>(flower()).entities; }
};

Bench branch_standing(const std::string& species) {
    SceneDef scene = test::kenzan_bench();
    scene.flowers.push_back({species, Placement::inserted, {0.0, 0.0, 0.0}, glm::normalize(glm::dvec3{0.1, 0.0, 1.0}), 0.013});
    scene.hands.push_back({1, {0.15, -0.15, 0.3}, 0.02, ""});
    Bench b;
    b.w = test::world_of(scene);
    b.clock = std::make_unique<sched::DeterministicClock>(b.w->schedule);
    return b;
}

void hold_hand_at(World& w, glm::dvec3 at) {
    std::ostringstream csv;
    csv << "time_s,x_m,y_m,z_m,rx_rad,ry_rad,rz_rad,buttons\n0," << at.x << "," << at.y << "," << at.z << ",0,0,0,0\n"
        << "100," << at.x << "," << at.y << "," << at.z << ",0,0,0,0\n";
    w.attach_device(1, std::make_unique<devices::ScriptedDevice>(*devices::parse_trajectory(csv.str(), "hold"), devices::ScriptedDevice::Mode::interpolate));
}

std::size_t twig_count(const std::vector<BranchDef>& branches) {
    std::size_t n = 0;
    for (const auto& b : branches) n += b.count * (1 + twig_count(b.branches));
    return n;
}

std::string with_branches(const std::string& branches) {
    return R"({"format": "ikebana-species/1", "id": "test_branch", "branch": "hard",
      "stem": {"length_mm": 300, "diameter_mm": 6, "segments": 12, "mass_g": 10, "youngs_modulus_mpa": 3000},
      "branches": )" + branches + R"(,
      "resistance": {"model": "hard_eq6", "cortex_tip_gf_per_mm": 711, "cortex_trunk_gf_per_mm": 316, "pith_tip_gf_per_mm": 40,
                     "pith_trunk_gf_per_mm": 7, "pith_diameter_mm": 2},
      "deterioration": {"model": "none"}, "breakage": {"model": "none"}})";
}

} // namespace

// The shipped branches are forked: a willow with long twigs, a cherry with side twigs and spurs of their
// own, an ume; each twig leaves its stem from a point of it, every twig listed after its parent.
TEST(Branches, ShippedBranchesAreForkedAndTheirTwigsGrowFromTheirStems) {
    for (const char* id : {"willow_branch", "cherry_branch", "ume_branch"}) {
        auto sp = load_species(id);
        ASSERT_TRUE(sp) << sp.error().message;
        ASSERT_FALSE(sp->branches.empty()) << id;
        Bench b = branch_standing(id);
        ASSERT_TRUE(b.w);
        const auto& twigs = b.twigs();
        EXPECT_EQ(twigs.size(), twig_count(sp->branches)) << id;
        std::vector<ecs::Entity> seen{b.flower()};
        for (const ecs::Entity t : twigs) {
            const auto& fork = b.w->sim.get<StemFork>(t);
            EXPECT_NE(std::find(seen.begin(), seen.end(), fork.parent), seen.end()) << id << ": a twig after its parent";
            const auto& parent = b.w->sim.get<StemPoints>(fork.parent).position_m;
            ASSERT_LT(fork.at_point, parent.size());
            EXPECT_GE(fork.at_point, 1u);
            EXPECT_EQ(b.w->sim.get<StemPoints>(t).position_m.front(), parent[fork.at_point]) << id << ": its first point is its parent's";
            seen.push_back(t);
        }
    }
    auto cherry = load_species("cherry_branch");
    ASSERT_TRUE(cherry);
    EXPECT_FALSE(cherry->branches[0].branches.empty()) << "the cherry's side twigs have spurs of their own";
}

// Carried with the stem: a branch standing in the pins for two seconds keeps every twig on its fork
// and at its angle (the stem and its twigs are one body), and nothing runs away.
TEST(Branches, TwigsStayOnTheirForksAtTheirAnglesAsTheBranchSettles) {
    Bench b = branch_standing("cherry_branch");
    ASSERT_TRUE(b.w);
    b.clock->run_for_us(2'000'000);
    double kinetic = 0.0;
    for (const ecs::Entity t : b.twigs()) {
        const auto& fork = b.w->sim.get<StemFork>(t);
        const auto& parent = b.w->sim.get<StemPoints>(fork.parent);
        const auto& points = b.w->sim.get<StemPoints>(t);
        EXPECT_LT(glm::length(points.position_m.front() - parent.position_m[fork.at_point]), 1e-12);
        const glm::dvec3 e_in = glm::normalize(parent.position_m[fork.at_point] - parent.position_m[fork.at_point - 1]);
        const glm::dvec3 e_out = glm::normalize(points.position_m[1] - points.position_m[0]);
        EXPECT_NEAR(std::acos(std::clamp(glm::dot(e_in, e_out), -1.0, 1.0)), fork.angle_rad, 0.15) << "the fork keeps its angle";
        for (std::size_t i = 0; i < points.position_m.size(); ++i) kinetic += 0.5 * points.mass_kg[i] * glm::dot(points.velocity_m_s[i], points.velocity_m_s[i]);
    }
    EXPECT_LT(kinetic, 1e-6) << "settled";
    EXPECT_FALSE(b.w->sim.get<KenzanGrip>(b.flower()).fallen);
}

// A twig's first point is its stem's: after the stem is cut shorter (its points laid anew), each twig
// still grows where it did on the stem, the same way below the top, and one on the part cut off is gone.
TEST(Branches, ACutStemKeepsItsTwigsWhereTheyGrowAndTheCutPartsTwigsGoWithIt) {
    Bench b = branch_standing("willow_branch");
    ASSERT_TRUE(b.w);
    b.clock->run_for_us(200'000);
    const auto& rest = b.w->sim.get<StemRestShape>(b.flower());
    const double length = std::accumulate(rest.segment_length_m.begin(), rest.segment_length_m.end(), 0.0);
    const std::size_t segments = rest.segment_length_m.size();
    std::vector<double> from_top;
    for (const ecs::Entity t : b.twigs()) from_top.push_back(length * (1.0 - static_cast<double>(b.w->sim.get<StemFork>(t).at_point) / static_cast<double>(segments)));
    const double cut = 0.16; // the willow's lowest twig is 0.3 up its 450 mm: this takes it
    b.w->sim.emplace_or_replace<CutRequest>(b.flower(), CutRequest{cut});
    b.clock->run_for_us(1000);
    const auto& twigs = b.twigs();
    std::size_t expected = 0;
    for (const double d : from_top) expected += d < length - cut - 0.5 * (length - cut) / static_cast<double>(segments) ? 1 : 0;
    ASSERT_LT(twigs.size(), from_top.size()) << "a twig grew on the part cut off";
    EXPECT_EQ(twigs.size(), expected);
    const double kept = length - cut;
    for (const ecs::Entity t : twigs) {
        const auto& fork = b.w->sim.get<StemFork>(t);
        const double now_from_top = kept * (1.0 - static_cast<double>(fork.at_point) / static_cast<double>(segments));
        const bool matches = std::any_of(from_top.begin(), from_top.end(), [&](double d) { return std::abs(d - now_from_top) <= kept / static_cast<double>(segments); });
        EXPECT_TRUE(matches) << "a twig " << now_from_top << " m below the top";
        EXPECT_EQ(b.w->sim.get<StemPoints>(t).position_m.front(), b.w->sim.get<StemPoints>(b.flower()).position_m[fork.at_point]);
    }
    b.clock->run_for_us(1'000'000);
    for (const ecs::Entity t : b.twigs()) {
        for (const auto& v : b.w->sim.get<StemPoints>(t).velocity_m_s) EXPECT_LT(glm::length(v), 1.0) << "no twig flung by the cut";
    }
}

// A stem's leaves stay where they grow when its bottom is cut (its points laid anew, closer together):
// each at the point nearest its old distance below the top, and those on the part cut off go with it.
// (They kept their point numbers once: a chrysanthemum cut to a third had its lower leaves squeezed down
// into the water.)
TEST(Branches, ACutStemKeepsItsLeavesWhereTheyGrowAndTheCutPartsLeavesGoWithIt) {
    Bench b = branch_standing("chrysanthemum");
    ASSERT_TRUE(b.w);
    b.clock->run_for_us(100'000);
    const auto& rest = b.w->sim.get<StemRestShape>(b.flower());
    const double length = std::accumulate(rest.segment_length_m.begin(), rest.segment_length_m.end(), 0.0);
    const auto segments = static_cast<double>(rest.segment_length_m.size());
    const auto leaves_from_top = [&](double stem_length) {
        std::vector<double> from_top;
        for (const ecs::Entity child : b.w->sim.get<const ecs::Children>(b.flower()).entities) {
            const auto* part = b.w->sim.try_get<const Part>(child);
            if (part && part->kind == PartKind::leaf) from_top.push_back(stem_length * (1.0 - part->stem_point / segments));
        }
        return from_top;
    };
    const std::vector<double> before = leaves_from_top(length);
    ASSERT_GE(before.size(), 4u);
    const double cut = 0.5 * length;
    b.w->sim.emplace_or_replace<CutRequest>(b.flower(), CutRequest{cut});
    b.clock->run_for_us(1000);
    const double kept = length - cut;
    const std::vector<double> after = leaves_from_top(kept);
    std::size_t expected = 0;
    for (const double d : before) expected += d < kept - 0.5 * kept / segments ? 1 : 0;
    ASSERT_LT(expected, before.size()) << "some grew on the half cut off";
    EXPECT_EQ(after.size(), expected);
    for (const double d : after) {
        EXPECT_TRUE(std::any_of(before.begin(), before.end(), [&](double was) { return std::abs(was - d) <= kept / segments; })) << d << " m below the top";
    }
}

// Secateurs at the hand: P with the cube on a twig cuts it off at its fork; it falls to the table, its
// spur and blossoms with it, and is drawn where it lies; the branch keeps its other twigs.
TEST(Branches, APrunedTwigFallsToTheTableWithItsSpurAndBlossoms) {
    Bench b = branch_standing("cherry_branch");
    ASSERT_TRUE(b.w);
    b.clock->run_for_us(1'000'000);
    const std::size_t before = b.twigs().size();
    // The top side twig (its spur is listed right after it).
    ecs::Entity target = ecs::null_entity;
    for (const ecs::Entity t : b.twigs()) {
        if (b.w->sim.get<StemFork>(t).parent == b.flower()) target = t;
    }
    ASSERT_FALSE(target.is_null());
    std::size_t going = 1;
    for (const ecs::Entity t : b.twigs()) going += b.w->sim.get<StemFork>(t).parent == target ? 1 : 0;
    ASSERT_GE(going, 2u) << "it has a spur";
    hold_hand_at(*b.w, b.w->sim.get<StemPoints>(target).position_m[1]);
    b.clock->run_for_us(300'000);
    ASSERT_TRUE(b.w->trainee.push({systems::TraineeCommand::Kind::prune, 1, 0.0}));
    b.clock->run_for_us(20'000);
    EXPECT_EQ(b.twigs().size(), before - going);
    ASSERT_TRUE(b.w->sim.all_of<Cutting>(target));
    EXPECT_FALSE(b.w->sim.all_of<StemFork>(target));
    EXPECT_EQ(b.w->sim.get<Twigs>(target).entities.size(), going - 1) << "its spur goes with it";
    hold_hand_at(*b.w, {0.2, -0.2, 0.3}); // out of its way
    b.clock->run_for_us(3'000'000);
    double highest = 0.0;
    for (const auto& x : b.w->sim.get<StemPoints>(target).position_m) highest = std::max(highest, x.z);
    EXPECT_LT(highest, 0.03) << "it lies on the table";
    const auto& frame = b.w->main.resource<const systems::ReceivedFrames>()->latest();
    ASSERT_EQ(frame.cuttings.size(), 1u);
    EXPECT_EQ(frame.cuttings[0].pieces.size(), going);
    std::size_t blossoms = 0;
    for (const auto& piece : frame.cuttings[0].pieces) blossoms += piece.parts.size();
    EXPECT_GT(blossoms, 0u) << "drawn with its blossoms";
    EXPECT_FALSE(b.w->sim.get<KenzanGrip>(b.flower()).fallen) << "the branch stands";
}

// A leaf is stripped, not a twig, when the cube is on the leaf and no twig is nearer: the flower loses
// that leaf, and it falls on a stalk of its own.
TEST(Branches, ALeafUnderTheHandIsStrippedAndFalls) {
    Bench b = branch_standing("sunflower");
    ASSERT_TRUE(b.w);
    b.clock->run_for_us(500'000);
    const auto leaves_of = [&](ecs::Entity e) {
        std::size_t n = 0;
        if (const auto* children = b.w->sim.try_get<ecs::Children>(e)) {
            for (const ecs::Entity c : children->entities) n += b.w->sim.all_of<Part>(c) && b.w->sim.get<Part>(c).kind == PartKind::leaf ? 1 : 0;
        }
        return n;
    };
    const std::size_t leaves = leaves_of(b.flower());
    ASSERT_GT(leaves, 0u);
    // The drawn frame says where a leaf's middle is: aim there.
    const auto& frame = b.w->main.resource<const systems::ReceivedFrames>()->latest();
    glm::dvec3 aim{0.0};
    bool found = false;
    for (const auto& p : frame.flowers[0].parts) {
        if (p.kind != PartKind::leaf) continue;
        const auto& x = frame.flowers[0].points_m;
        aim = systems::physics::attachment_frame(x, p.stem_point, frame.flowers[0].directors).place(p.offset_m); // as drawn: its middle
        found = true;
        break;
    }
    ASSERT_TRUE(found);
    hold_hand_at(*b.w, aim);
    b.clock->run_for_us(300'000);
    ASSERT_TRUE(b.w->trainee.push({systems::TraineeCommand::Kind::prune, 1, 0.0}));
    b.clock->run_for_us(20'000);
    EXPECT_EQ(leaves_of(b.flower()), leaves - 1);
    std::size_t loose = 0;
    b.w->sim.view<const Cutting>().each([&](ecs::Entity e, const Cutting& c) {
        ++loose;
        EXPECT_EQ(c.species, "sunflower");
        EXPECT_EQ(leaves_of(e), 1u) << "the leaf on its stalk";
    });
    EXPECT_EQ(loose, 1u);
}

// Branches in the species file: read in SI, each problem named by its JSON path; a twig that runs off its
// parent's top, too many twigs in all, or twigs too deep are refused.
TEST(Branches, BranchFieldsAreReadAndCheckedAtTheirPaths) {
    const auto ok = parse_species(with_branches(R"([{"count": 3, "at": 0.4, "every": 0.2, "angle_deg": 40, "turn_deg": 180, "shrink": 0.1,
        "length_mm": 100, "diameter_mm": 2, "segments": 5, "mass_g": 1, "rest_bend_deg": -30,
        "branches": [{"at": 0.5, "angle_deg": 30, "length_mm": 30, "diameter_mm": 1, "segments": 3, "mass_g": 0.1}]}])"), "test_branch.json");
    ASSERT_TRUE(ok) << ok.error().message;
    ASSERT_EQ(ok->branches.size(), 1u);
    const BranchDef& b = ok->branches[0];
    EXPECT_EQ(b.count, 3u);
    EXPECT_NEAR(b.angle_rad, 40.0 * M_PI / 180.0, 1e-12);
    EXPECT_NEAR(b.turn_rad, M_PI, 1e-12);
    EXPECT_NEAR(b.length_m, 0.1, 1e-12);
    EXPECT_NEAR(b.rest_bend_rad, -30.0 * M_PI / 180.0, 1e-12) << "negative: weeping";
    EXPECT_NEAR(b.branches[0].turn_rad, 137.5 * M_PI / 180.0, 1e-12) << "the golden angle by default";

    const auto missing = parse_species(with_branches(R"([{"at": 0.4, "length_mm": 100, "diameter_mm": 2, "segments": 5, "mass_g": 1}])"), "t.json");
    ASSERT_FALSE(missing);
    EXPECT_NE(missing.error().message.find("t.json: /branches/0/angle_deg: "), std::string::npos) << missing.error().message;
    const auto past = parse_species(with_branches(R"([{"count": 4, "at": 0.7, "every": 0.2, "angle_deg": 40, "length_mm": 100, "diameter_mm": 2, "segments": 5, "mass_g": 1}])"), "t.json");
    ASSERT_FALSE(past);
    EXPECT_EQ(past.error().message, "t.json: /branches/0/every: its 4 twigs from 0.7 every 0.2 run past the parent's top (1)");
    const auto many = parse_species(with_branches(R"([{"count": 20, "at": 0.1, "every": 0.01, "angle_deg": 40, "length_mm": 100, "diameter_mm": 2, "segments": 5, "mass_g": 1,
        "branches": [{"count": 10, "at": 0.5, "angle_deg": 30, "length_mm": 30, "diameter_mm": 1, "segments": 3, "mass_g": 0.1}]}])"), "t.json");
    ASSERT_FALSE(many);
    EXPECT_EQ(many.error().message, "t.json: /branches: makes 220 twigs in all, more than 120: each is simulated at 1 kHz");
    const std::string twig = R"({"at": 0.5, "angle_deg": 30, "length_mm": 30, "diameter_mm": 1, "segments": 3, "mass_g": 0.1)";
    const std::string deep = "[" + twig + R"(, "branches": [)" + twig + R"(, "branches": [)" + twig + R"(, "branches": [)" + twig + R"(, "branches": [)" + twig + "}]}]}]}]}]";
    const auto too_deep = parse_species(with_branches(deep), "t.json");
    ASSERT_FALSE(too_deep);
    EXPECT_NE(too_deep.error().message.find("/branches/0/branches/0/branches/0/branches/0/branches: twigs go at most 4 deep"), std::string::npos) << too_deep.error().message;
}
