#include <gtest/gtest.h>

#include <algorithm>

#include "components/flower.hpp"
#include "components/stem.hpp"
#include "engine/sched/clocks.hpp"
#include "game/scene/scene.hpp"
#include "game/world/summary.hpp"
#include "game/world/world.hpp"
#include "systems/presentation/draw_list.hpp"
#include "systems/presentation/frame_channel.hpp"

using namespace ikebana;
using namespace ikebana::game;

namespace {
SceneDef default_scene() {
    auto scene = load_scene(std::string(IKEBANA_ASSET_DIR) + "/scenes/default.json");
    EXPECT_TRUE(scene) << (scene ? "" : scene.error().message);
    return *scene;
}

std::uint64_t run(const SceneDef& scene, double seconds, WorldOptions options = {}) {
    auto world = World::create(scene, options);
    EXPECT_TRUE(world) << (world ? "" : world.error().message);
    sched::DeterministicClock clock((*world)->schedule);
    clock.run_for_us(static_cast<std::int64_t>(seconds * 1e6));
    return (*world)->state_hash();
}
} // namespace

TEST(World, SameSceneTwiceGivesBitIdenticalState) {
    const auto scene = default_scene();
    EXPECT_EQ(run(scene, 1.5), run(scene, 1.5));
}

TEST(World, ChangedInputChangesTheState) {
    const auto scene = default_scene();
    auto nudged = scene;
    nudged.flowers[0].direction = glm::normalize(nudged.flowers[0].direction + glm::dvec3{0.0, 1e-6, 0.0});
    EXPECT_NE(run(scene, 1.5), run(nudged, 1.5));
    auto other_gravity = scene;
    other_gravity.gravity_m_s2.z = -9.7;
    EXPECT_NE(run(scene, 1.5), run(other_gravity, 1.5));
}

TEST(World, RatesComeFromSceneAndCommandLine) {
    auto scene = default_scene();
    scene.rates_hz["render"] = 60.0;
    auto world = World::create(scene, WorldOptions{.rate_overrides = {"position_check=20"}, .force_scheme = {}, .main_lane_systems = {}});
    ASSERT_TRUE(world);
    sched::DeterministicClock clock((*world)->schedule);
    clock.run_for_us(1'000'000);
    EXPECT_EQ((*world)->schedule.find("publish_frame")->stats.calls, 60u);
    EXPECT_EQ((*world)->schedule.rates().hz("position_check"), 20.0);
}

TEST(World, BadRateIsRefusedWithItsName) {
    const auto scene = default_scene();
    auto world = World::create(scene, WorldOptions{.rate_overrides = {"render=0"}, .force_scheme = {}, .main_lane_systems = {}});
    ASSERT_FALSE(world);
    EXPECT_NE(world.error().message.find("render"), std::string::npos);
    auto unknown = World::create(scene, WorldOptions{.rate_overrides = {"warp=10"}, .force_scheme = {}, .main_lane_systems = {}});
    ASSERT_FALSE(unknown);
    EXPECT_NE(unknown.error().message.find("unknown rate 'warp'"), std::string::npos);
}

TEST(World, MissingSpeciesIsReportedAndNothingIsBuilt) {
    auto scene = default_scene();
    scene.flowers[1].species = "no_such_flower";
    auto world = World::create(scene);
    ASSERT_FALSE(world);
    EXPECT_EQ(world.error().code, ErrorCode::not_found);
    EXPECT_NE(world.error().message.find("no_such_flower.json"), std::string::npos);
}

TEST(World, FlowerOwnsItsPartsWithCollisionTags) {
    auto world = World::create(default_scene());
    ASSERT_TRUE(world);
    auto& r = (*world)->sim;
    const auto flower = (*world)->flowers[0].entity; // the sunflower
    const auto parts = ecs::children_of(r, flower); // a copy: destroying the flower ends the list
    std::size_t stem = 0, petals = 0, leaves = 0, tagged_once = 0;
    for (const auto part : parts) {
        const auto& p = r.get<components::Part>(part);
        stem += p.kind == components::PartKind::stem;
        petals += p.kind == components::PartKind::petal;
        leaves += p.kind == components::PartKind::leaf;
        const int tags = r.all_of<components::ActiveCollider>(part) + r.all_of<components::PassiveCollider>(part) +
                         r.all_of<components::InactiveCollider>(part);
        tagged_once += tags == 1;
        if (p.kind == components::PartKind::petal) {
            EXPECT_TRUE(r.all_of<components::InactiveCollider>(part));
        }
    }
    EXPECT_EQ(stem, 20u) << "one part per stem segment";
    EXPECT_EQ(petals, 42u) << "21 rays in two rings";
    EXPECT_EQ(leaves, 2u);
    EXPECT_EQ(tagged_once, parts.size()) << "every part carries exactly one collision tag";
    r.destroy(flower);
    for (const auto part : parts) EXPECT_FALSE(r.valid(part));
}

TEST(World, DefaultSceneStaysPutAndFinite) {
    auto world = World::create(default_scene());
    ASSERT_TRUE(world);
    sched::DeterministicClock clock((*world)->schedule);
    clock.run_for_us(5'000'000);
    const auto s = summarize(**world);
    EXPECT_EQ(s.flowers, 2u);
    EXPECT_LT(s.kinetic_j, 1e-6) << "everything has settled";
    // It sags from 30 to about 50 degrees while the pins give way (its bottom stands on the kenzan's
    // plate, 13 mm deep), then they hold it: it stands, its top about 150 mm up.
    ASSERT_FALSE(s.flower_states.empty());
    EXPECT_TRUE(s.flower_states[0].in_kenzan);
    EXPECT_FALSE(s.flower_states[0].fallen) << "the inserted sunflower still stands";
    EXPECT_GT(s.highest_point_m, 0.13);
    EXPECT_EQ(s.frames_received, 150u) << "the main lane received every published frame";
}

// Parts say how they sit: a chrysanthemum's petals in rings, each inner ring shorter, more upright and
// turned half a step, their shades varied within the species' bound; its leaves stay leaves (with more
// parts than definitions' counts, the spawned parts once took the petals' places and tags).
TEST(World, PetalsSitInRingsAndLeavesStayLeaves) {
    auto sp = load_species("chrysanthemum");
    ASSERT_TRUE(sp) << sp.error().message;
    const auto& petals = sp->parts.front();
    ASSERT_EQ(petals.kind, components::PartKind::petal);
    ASSERT_GT(petals.whorls, 1u);
    const auto parts = parts_of(*sp, 20);
    std::size_t leaves_defined = 0, petals_made = 0, leaves_made = 0;
    for (const auto& d : sp->parts) leaves_defined += d.kind == components::PartKind::leaf ? d.count * d.whorls : 0;
    float lo = 2.0f, hi = 0.0f;
    for (const auto& p : parts) {
        petals_made += p.kind == components::PartKind::petal ? 1 : 0;
        leaves_made += p.kind == components::PartKind::leaf ? 1 : 0;
        if (p.kind == components::PartKind::petal) {
            lo = std::min(lo, p.shade);
            hi = std::max(hi, p.shade);
        }
    }
    EXPECT_EQ(petals_made, petals.count * petals.whorls);
    EXPECT_EQ(leaves_made, leaves_defined);
    EXPECT_GE(lo, 1.0f - static_cast<float>(petals.colour_variation) - 1e-6f);
    EXPECT_LE(hi, 1.0f + static_cast<float>(petals.colour_variation) + 1e-6f);
    EXPECT_GT(hi - lo, 0.5f * static_cast<float>(petals.colour_variation)) << "not all alike";
    const auto& outer = parts[0].offset_m;
    const auto& inner = parts[petals.count].offset_m; // the second ring's first
    EXPECT_LT(glm::length(inner), glm::length(outer)) << "shorter";
    EXPECT_GT(inner.z / glm::length(inner), outer.z / glm::length(outer)) << "more upright";
    EXPECT_NEAR(outer.z / glm::length(outer), std::sin(petals.tilt_rad), 1e-9) << "the outer ring at the species' tilt";

    // Spawned: every leaf a leaf, passive as the species says; every petal inactive.
    SceneDef scene = default_scene();
    scene.flowers = {{"chrysanthemum", Placement::inserted, {0, 0, 0.010}, {0, 0, 1}, 0.013}};
    scene.sample.clear();
    auto world = World::create(scene);
    ASSERT_TRUE(world) << world.error().message;
    std::size_t passive_leaves = 0, inactive_petals = 0;
    (*world)->sim.view<const components::Part>().each([&](ecs::Entity e, const components::Part& p) {
        if (p.kind == components::PartKind::leaf && (*world)->sim.try_get<const components::PassiveCollider>(e)) ++passive_leaves;
        if (p.kind == components::PartKind::petal && (*world)->sim.try_get<const components::InactiveCollider>(e)) ++inactive_petals;
    });
    EXPECT_EQ(passive_leaves, leaves_defined);
    EXPECT_EQ(inactive_petals, petals.count * petals.whorls);
}

namespace {
// What is drawn of one flower of `species` standing alone in the kenzan, a tenth of a second in.
render::DrawList drawn_standing_alone(const std::string& species) {
    SceneDef scene = default_scene();
    scene.flowers = {{species, Placement::inserted, {0, 0, 0.010}, {0, 0, 1}, 0.013}};
    scene.sample.clear();
    auto world = World::create(scene);
    EXPECT_TRUE(world) << world.error().message;
    if (!world) return {};
    sched::DeterministicClock clock((*world)->schedule);
    clock.run_for_us(100'000);
    return systems::build_draw_list((*world)->main.resource<const systems::ReceivedFrames>()->latest());
}
} // namespace

// How many of these parts, and of their twigs' (each twig as often as it is made), are curled by `cup`.
std::size_t curled_parts(const std::vector<PartDef>& parts, const std::vector<BranchDef>& branches, float cup, std::uint32_t points) {
    const auto made = parts_of(parts, points);
    std::size_t n = static_cast<std::size_t>(std::count_if(made.begin(), made.end(), [&](const components::Part& p) {
        return std::abs(p.cup_rad - cup) < 1e-5f && p.cup_rad != 0.0f;
    }));
    for (const auto& b : branches) n += b.count * curled_parts(b.parts, b.branches, cup, b.segments + 1);
    return n;
}

// A part's cup reaches the picture, on the stem and on its twigs: a cherry's blossoms curl (each
// instance carries its bend, one unit long, so the bend per unit is the species' cup), a willow's leaves
// droop, and a sunflower's rays stay flat.
TEST(World, CuppedPartsAreDrawnCurled) {
    for (const auto& [id, cup_deg] : {std::pair{"cherry_branch", 45.0}, std::pair{"willow_branch", -20.0}, std::pair{"sunflower", 0.0}}) {
        auto sp = load_species(id);
        ASSERT_TRUE(sp) << sp.error().message;
        const auto cup = static_cast<float>(cup_deg * glm::pi<double>() / 180.0);
        const std::size_t curled = curled_parts(sp->parts, sp->branches, cup, sp->segments + 1);
        if (cup_deg == 0.0) {
            EXPECT_EQ(curled, 0u) << id;
            continue;
        }
        EXPECT_GT(curled, 0u) << id;
        const auto list = drawn_standing_alone(id);
        std::size_t bent = 0;
        for (const auto& b : list.batches) {
            for (const auto& inst : b.instances) bent += std::abs(inst.bend_rad_per_unit - cup) < 1e-5f ? 1 : 0;
        }
        EXPECT_EQ(bent, curled) << id << ": every curled part drawn curled, the twigs' too";
    }
}

// A vase stands on the table and rises to its rim, however high its fill (a kubari, where the kenzan
// stands) comes: drawn from its fill's floor only, it hung in the air over its own shadow.
TEST(World, AVaseIsDrawnFromTheTableToItsRim) {
    SceneDef scene = default_scene();
    scene.flowers.clear();
    scene.sample.clear();
    scene.container = ContainerDef{.shape = ContainerShape::vase, .width_m = 0.12, .front_to_back_m = 0.12, .depth_m = 0.15, .water_depth_m = 0.12};
    auto world = World::create(scene);
    ASSERT_TRUE(world) << world.error().message;
    sched::DeterministicClock clock((*world)->schedule);
    clock.run_for_us(100'000);
    const auto& frame = (*world)->main.resource<const systems::ReceivedFrames>()->latest();
    ASSERT_TRUE(frame.container);
    const auto list = systems::build_draw_list(frame);
    double lowest = 1e9, highest = -1e9;
    for (const auto& b : list.batches) {
        if (b.mesh != "cube") continue;
        for (const auto& inst : b.instances) {
            // A wall piece: a box as tall as the vase (its model's third column is its height).
            const glm::vec3 up(inst.model[2]);
            if (glm::length(up) < 0.1f) continue;
            lowest = std::min(lowest, static_cast<double>(inst.model[3].z - 0.5f * up.z));
            highest = std::max(highest, static_cast<double>(inst.model[3].z + 0.5f * up.z));
        }
    }
    EXPECT_NEAR(lowest, scene.table_height_m, 1e-6) << "it stands on the table";
    EXPECT_NEAR(highest, frame.container->rim_z_m, 1e-6) << "and reaches its rim";
    EXPECT_GT(frame.container->floor_z_m - scene.table_height_m, 0.1) << "its fill comes up near the mouth";
}

// Parts without a mesh file are drawn: the iris's sword leaves and its petals reach the draw list under
// their shapes' names, as many as the species has.
TEST(World, PartsWithoutAMeshFileAreDrawnAsTheirShapes) {
    const auto list = drawn_standing_alone("iris");
    std::size_t swords = 0, petals = 0;
    for (const auto& b : list.batches) {
        if (b.mesh.rfind("part:sword:", 0) == 0) swords += b.instances.size();
        if (b.mesh.rfind("part:petal:", 0) == 0) petals += b.instances.size();
        EXPECT_FALSE(b.mesh.empty() && !b.instances.empty()) << "nothing is drawn under no name";
    }
    EXPECT_EQ(swords, 3u);
    EXPECT_EQ(petals, 6u);
}

// Pick by ray (issue 59): a press takes the stem drawn under the cursor, whatever the hand's depth.
namespace {
components::FlowerStatus lying_stem(double y_m, double diameter_m) {
    components::FlowerStatus f{};
    f.species = "chrysanthemum";
    f.diameter_m = diameter_m;
    for (int i = 0; i <= 10; ++i) f.points_m.push_back({-0.15 + 0.03 * i, y_m, 0.01});
    return f;
}
} // namespace

TEST(StemUnderRay, TheNearerOfTwoStemsOnOneLineOfSightIsTheOneTakenAtThePointUnderTheCursor) {
    components::FrameSnapshot frame{};
    frame.flowers.push_back(lying_stem(0.20, 0.006)); // far
    frame.flowers.push_back(lying_stem(0.05, 0.006)); // near
    // From the viewer's eye above and in front, through x = 0.04 on the near stem.
    const glm::dvec3 eye{0.0, -0.50, 0.40};
    const glm::dvec3 target{0.04, 0.05, 0.01};
    const auto hit = systems::stem_under_ray(frame, eye, target - eye);
    ASSERT_TRUE(hit);
    EXPECT_EQ(hit->flower, 1u);
    EXPECT_FALSE(hit->twig);
    const glm::dvec3 at = eye + hit->t_m * glm::normalize(target - eye);
    EXPECT_LT(glm::length(at - target), 0.004) << "the hand goes to the point under the cursor";
    EXPECT_EQ(hit->point, 6u); // x = 0.03, the stem point nearest 0.04
    // The held stem is not offered: the ray then finds the one behind it.
    const auto behind = systems::stem_under_ray(frame, eye, glm::dvec3{0.04, 0.20, 0.01} - eye, 0.006, std::size_t{1});
    ASSERT_TRUE(behind);
    EXPECT_EQ(behind->flower, 0u);
}

TEST(StemUnderRay, AThinStemIsTakenWithinSixMillimetresAndNothingBeyondIt) {
    components::FrameSnapshot frame{};
    frame.flowers.push_back(lying_stem(0.10, 0.003));
    const glm::dvec3 eye{0.0, -0.50, 0.40};
    EXPECT_TRUE(systems::stem_under_ray(frame, eye, glm::dvec3{0.0, 0.10, 0.015} - eye));
    EXPECT_FALSE(systems::stem_under_ray(frame, eye, glm::dvec3{0.0, 0.10, 0.03} - eye));
    EXPECT_FALSE(systems::stem_under_ray(frame, eye, glm::dvec3{0.30, 0.10, 0.01} - eye)) << "past its tip";
    EXPECT_FALSE(systems::stem_under_ray(frame, eye, eye - glm::dvec3{0.0, 0.10, 0.01})) << "behind the eye";
}
