#include <gtest/gtest.h>

#include "components/flower.hpp"
#include "components/stem.hpp"
#include "engine/sched/clocks.hpp"
#include "game/scene/scene.hpp"
#include "game/world/summary.hpp"
#include "game/world/world.hpp"

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
    EXPECT_EQ(petals, 16u);
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
