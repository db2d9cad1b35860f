#include <gtest/gtest.h>

#include <cmath>

#include <filesystem>
#include <fstream>

#include "engine/sched/clocks.hpp"
#include "game/scene/placement_checks.hpp"
#include "game/scene/scene.hpp"
#include "game/world/summary.hpp"
#include "game/world/world.hpp"

using namespace ikebana;
using namespace ikebana::game;

namespace {
SceneDef default_scene() {
    auto scene = load_scene(std::string(IKEBANA_ASSET_DIR) + "/scenes/default.json");
    EXPECT_TRUE(scene) << scene.error().message;
    return *scene;
}

std::string refusal(const SceneDef& scene) {
    auto world = World::create(scene);
    EXPECT_FALSE(world) << "the world was built";
    return world ? std::string() : world.error().message;
}
} // namespace

TEST(PlacementChecks, AnInsertedFlowerFarFromTheKenzanIsRefused) {
    auto scene = default_scene();
    scene.flowers[0].base_m = {0.5, 0.0, 0.01};
    EXPECT_EQ(refusal(scene),
              "default.json: /flowers/0/base_mm: an inserted flower must stand on the kenzan's pins, which span x -40 to 40 mm and y -40 to 40 mm; "
              "this one is at (500, 0) mm (use \"placement\": \"lying\" for a flower on the table)");
}

TEST(PlacementChecks, TwoStemsInOneHoleAreRefused) {
    auto scene = default_scene();
    for (int i = 0; i < 200; ++i) scene.flowers.push_back(scene.flowers[0]);
    EXPECT_EQ(refusal(scene), "default.json: /flowers/2/base_mm: overlaps /flowers/0: their bottoms are 0.0 mm apart and the stems 7.5 and 7.5 mm "
                              "thick; two stems cannot share one place on the pins");
}

TEST(PlacementChecks, AStemPointingDownIsRefused) {
    auto scene = default_scene();
    scene.flowers[0].direction = {0, 0, -1};
    EXPECT_EQ(refusal(scene), "default.json: /flowers/0/direction: an inserted stem must point up out of the pins, at least 10 degrees above the "
                              "horizontal; this one points 90 degrees below it");
}

TEST(PlacementChecks, ASpeciesErrorNamesTheSceneAndTheFlower) {
    auto scene = default_scene();
    scene.flowers[1].species = "no_such_flower";
    const auto message = refusal(scene);
    EXPECT_EQ(message.rfind("default.json: /flowers/1/species: ", 0), 0u) << message;
    EXPECT_NE(message.find("no_such_flower"), std::string::npos) << message;
}

TEST(PlacementChecks, CoordinatesBeyondTheWorkspaceAreRefusedWhereTheyAreRead) {
    const std::string base = R"({"format": "ikebana-scene/1", "kenzan": {"layout": "standard"}, )";
    const auto flower = parse_scene(base + R"("flowers": [{"species": "sunflower", "placement": "lying", "base_mm": [1e18, 0, 0], "direction": [1, 0, 0]}]})", "far.json");
    ASSERT_FALSE(flower);
    EXPECT_EQ(flower.error().message, "far.json: /flowers/0/base_mm/0: expected a number in [-2000, 2000], got 1e+18");
    const auto hand = parse_scene(base + R"("hands": [{"hand": "left", "position_mm": [1e300, 0, 0]}]})", "hand.json");
    ASSERT_FALSE(hand);
    EXPECT_EQ(hand.error().message, "hand.json: /hands/0/position_mm/0: expected a number in [-2000, 2000], got 1e+300");
    const auto gravity = parse_scene(base + R"("gravity_m_s2": [0, 0, 1e300]})", "g.json");
    ASSERT_FALSE(gravity);
    EXPECT_EQ(gravity.error().message, "g.json: /gravity_m_s2/2: expected a number in [-100, 100], got 1e+300");
}

TEST(PlacementChecks, AScriptedHandOutsideTheWorkspaceIsRefused) {
    const auto dir = std::filesystem::temp_directory_path() / "ikebana_placement_checks";
    std::filesystem::create_directories(dir);
    {
        std::ofstream out(dir / "far.csv");
        out << "time_s,x_m,y_m,z_m,rx_rad,ry_rad,rz_rad,buttons\n0,0,0,0.1,0,0,0,0\n1,5,0,0.1,0,0,0,1\n";
    }
    auto scene = default_scene();
    scene.file = dir / "default.json"; // as if the scene lay beside its trajectories (a file names only files beside it or shipped)
    scene.hands[0].trajectory = (dir / "far.csv").string();
    EXPECT_EQ(refusal(scene), "default.json: /hands/0/trajectory: at 1.000 s the hand is at (5, 0, 0.1) m, outside the workspace (2 m from the "
                              "origin on each axis)");
    // Beyond any device's reach the trajectory itself is refused, with its line and column.
    {
        std::ofstream out(dir / "huge.csv");
        out << "time_s,x_m,y_m,z_m,rx_rad,ry_rad,rz_rad,buttons\n0,1e15,0,0.1,0,0,0,0\n";
    }
    scene.hands[0].trajectory = (dir / "huge.csv").string();
    EXPECT_EQ(refusal(scene), "default.json: /hands/0/trajectory: " + (dir / "huge.csv").string() + ":2:3: a position beyond the 10 m any device reaches");
}

TEST(PlacementChecks, TheShippedScenesPass) {
    for (const char* name : {"default.json", "arrangement.json"}) {
        auto scene = load_scene(std::string(IKEBANA_ASSET_DIR) + "/scenes/" + name);
        ASSERT_TRUE(scene) << scene.error().message;
        auto world = World::create(*scene);
        EXPECT_TRUE(world) << name << ": " << world.error().message;
    }
}

TEST(Summary, AFallenStemSaysWhenItFellAndWhatTheMomentsWereWhenThePinsGaveWay) {
    // A chrysanthemum leaning 20 degrees, pushed in only 4 mm: its few pins cannot hold its head's moment.
    auto scene = default_scene();
    scene.flowers.resize(1);
    scene.flowers[0].species = "chrysanthemum";
    scene.flowers[0].base_m = {-0.012, 0.0, 0.01};
    scene.flowers[0].direction = {std::sin(0.349), 0, std::cos(0.349)};
    scene.flowers[0].inserted_depth_m = 0.004;
    auto world = World::create(scene);
    ASSERT_TRUE(world) << world.error().message;
    sched::DeterministicClock clock((*world)->schedule);
    // Released upright, it sags towards its bend until the pins give way, and tips.
    bool seen_yielding = false;
    for (int step = 0; step < 200 && !seen_yielding; ++step) {
        clock.run_for_us(10'000);
        const auto now = summarize(**world);
        const auto& f = now.flower_states.at(0);
        if (f.fallen) break;
        if (f.in_kenzan && f.holding_moment_nm < f.gravity_moment_nm) {
            seen_yielding = true;
            EXPECT_NE(format_summary(now, 0.0).find("-> yielding"), std::string::npos) << "not 'stands' while the pins give way";
        }
    }
    EXPECT_TRUE(seen_yielding) << "the test needs a stem the pins cannot hold";
    clock.run_for_us(3'800'000);
    const auto late = summarize(**world);
    const auto& f = late.flower_states.at(0);
    ASSERT_TRUE(f.fallen);
    ASSERT_TRUE(f.yielded);
    EXPECT_GT(f.fell_at_s, 0.2);
    const auto text = format_summary(late, 4.0);
    EXPECT_NE(text.find("FELL at "), std::string::npos) << text;
    EXPECT_NE(text.find(": tipped over (the pins first gave way holding"), std::string::npos) << text;
    // The moments when the pins first gave way explain it either way: its weight asked more than they
    // held, or they gave to its swing after release (its weight asking less); never "under" a smaller load.
    if (f.yield_gravity_nm > f.yield_holding_nm) EXPECT_NE(text.find(" under "), std::string::npos) << text;
    else EXPECT_NE(text.find("as it swung after release"), std::string::npos) << text;
}

TEST(Summary, EveryInsertedFlowerOfTheShippedArrangementStandsForFourSeconds) {
    // Its chrysanthemums once stood between pins upright, bent by their own curve, and all fell in 2 s.
    auto scene = load_scene(std::string(IKEBANA_ASSET_DIR) + "/scenes/arrangement.json");
    ASSERT_TRUE(scene) << scene.error().message;
    auto world = World::create(*scene);
    ASSERT_TRUE(world) << world.error().message;
    sched::DeterministicClock clock((*world)->schedule);
    clock.run_for_us(4'000'000);
    const auto summary = summarize(**world);
    for (std::size_t i = 0; i < scene->flowers.size(); ++i) {
        if (scene->flowers[i].placement != Placement::inserted) continue;
        const auto& f = summary.flower_states[i];
        EXPECT_TRUE(f.in_kenzan) << i << " " << f.species;
        EXPECT_FALSE(f.fallen) << i << " " << f.species;
        EXPECT_GE(f.holding_moment_nm, f.gravity_moment_nm) << i << " " << f.species;
    }
}

TEST(Summary, AHapticRateTooLowForAStemIsNamedAndItsRunawayEnergyWarned) {
    auto scene = default_scene();
    {
        auto paper = World::create(scene);
        ASSERT_TRUE(paper);
        EXPECT_TRUE(startup_warnings(**paper).empty()) << "the paper's 1 kHz suits every shipped species here";
    }
    auto world = World::create(scene, WorldOptions{.rate_overrides = {"haptic=1"}, .force_scheme = {}, .main_lane_systems = {}});
    ASSERT_TRUE(world) << world.error().message;
    const auto warnings = startup_warnings(**world);
    ASSERT_EQ(warnings.size(), 2u);
    EXPECT_NE(warnings[0].find("below the 232 Hz the cherry_branch's stiffness needs"), std::string::npos) << warnings[0];
    EXPECT_NE(warnings[1].find("the sunflower's stiffness needs"), std::string::npos) << warnings[1];
    sched::DeterministicClock clock((*world)->schedule);
    clock.run_for_us(3'000'000);
    auto summary = summarize(**world);
    // The branch's energy once ran away at 1 Hz: its natural curve's hinges, pulled straight, pushed
    // in a plane that turned every step. With that torque fading near straight it stays bounded...
    EXPECT_LT(summary.flower_states[1].elastic_j, summary.flower_states[1].elastic_ceiling_j) << "the implicit step holds even at 1 Hz";
    EXPECT_EQ(format_summary(summary, 3.0).find("warning: cherry_branch's springs hold"), std::string::npos);
    // ... and should a stem's energy run away, the summary says so.
    summary.flower_states[1].elastic_j = 2.0 * summary.flower_states[1].elastic_ceiling_j;
    const auto text = format_summary(summary, 3.0);
    EXPECT_NE(text.find("warning: cherry_branch's springs hold"), std::string::npos) << text;
}

// On a round kenzan the grid's corners have no pins: a flower set there is refused, not left to fall.
TEST(PlacementChecks, AFlowerOutsideARoundKenzansCircleIsRefused) {
    auto scene = default_scene();
    scene.kenzan_layout = "round";
    scene.flowers.resize(1);
    scene.flowers[0].base_m = {0.026, 0.026, 0.010}; // inside the 15 x 15 grid's square, outside its circle
    scene.sample.clear();
    EXPECT_EQ(refusal(scene), "default.json: /flowers/0/base_mm: an inserted flower must stand on the kenzan's pins, which lie within 31 mm of its "
                              "centre (a round kenzan); this one is 37 mm from it (use \"placement\": \"lying\" for a flower on the table)");
    scene.flowers[0].base_m = {0.010, 0.0, 0.010};
    EXPECT_TRUE(World::create(scene)) << "inside the circle it stands";
}
