#include <gtest/gtest.h>

#include "game/kenzan/kenzan_layout.hpp"
#include "game/scene/scene.hpp"

using namespace ikebana::game;

TEST(Scene, DefaultSceneIsThePapersFigure1b) {
    const auto scene = load_scene(std::string(IKEBANA_ASSET_DIR) + "/scenes/default.json");
    ASSERT_TRUE(scene) << scene.error().message;
    ASSERT_EQ(scene->flowers.size(), 2u);
    EXPECT_EQ(scene->flowers[0].species, "sunflower");
    EXPECT_EQ(scene->hands.size(), 2u);
    EXPECT_EQ(scene->kenzan_layout, "standard");
    EXPECT_EQ(scene->rates_hz.at("position_check"), 16.0);
}

TEST(Scene, BadValuesNameTheirPath) {
    const auto scene = parse_scene(R"({"format": "ikebana-scene/1", "rates_hz": {"render": 0},
        "kenzan": {"layout": "standard"},
        "flowers": [{"species": "sunflower", "placement": "floating", "base_mm": [0, 0], "direction": [0, 0, 0]}]})",
                                   "s.json");
    ASSERT_FALSE(scene);
    const auto& m = scene.error().message;
    EXPECT_NE(m.find("s.json: /rates_hz/render: expected a number in [0.001, 100000], got 0"), std::string::npos) << m;
    EXPECT_NE(m.find("s.json: /flowers/0/placement: expected one of"), std::string::npos) << m;
    EXPECT_NE(m.find("s.json: /flowers/0/base_mm: expected at least 3 numbers, got 2"), std::string::npos) << m;
    EXPECT_NE(m.find("s.json: /flowers/0/direction: must not be the zero vector"), std::string::npos) << m;
}

TEST(Kenzan, StandardLayoutHasThePapersPitch) {
    const auto k = load_kenzan("standard");
    ASSERT_TRUE(k) << k.error().message;
    EXPECT_DOUBLE_EQ(k->pitch_m, 0.004);
    EXPECT_EQ(k->rows * k->columns, 400);
    EXPECT_GT(k->pin.tip_length_m, 0.0);
}

// The shipped round kenzan: 6 cm across, the standard pins within its circle.
TEST(Kenzan, TheRoundLayoutKeepsThePinsWithinItsCircle) {
    const auto k = load_kenzan("round");
    ASSERT_TRUE(k) << k.error().message;
    EXPECT_NEAR(k->round_radius_m, 0.029, 1e-9);
    int pins = 0;
    for (std::int32_t c = 0; c < k->columns; ++c) {
        for (std::int32_t r = 0; r < k->rows; ++r) pins += k->has_pin(c, r) ? 1 : 0;
    }
    EXPECT_EQ(pins, 169) << "as its notes say";
    const auto bad = parse_kenzan(R"({"format": "ikebana-kenzan/1", "id": "x", "shape": "oval", "pitch_mm": 4, "columns": 2, "rows": 2,
        "base_thickness_mm": 5, "pin": {"trunk_diameter_mm": 0.9, "trunk_length_mm": 10, "tip_length_mm": 1}})",
                                  "x.json");
    ASSERT_FALSE(bad);
    EXPECT_NE(bad.error().message.find("x.json: /shape:"), std::string::npos) << bad.error().message;
}

TEST(Kenzan, TouchingPinsAreRefused) {
    const auto k = parse_kenzan(R"({"format": "ikebana-kenzan/1", "id": "x", "pitch_mm": 1, "columns": 2, "rows": 2,
        "base_thickness_mm": 5, "pin": {"trunk_diameter_mm": 1.5, "trunk_length_mm": 10, "tip_length_mm": 1}})",
                                "x.json");
    ASSERT_FALSE(k);
    EXPECT_NE(k.error().message.find("x.json: /pin/trunk_diameter_mm: pins would touch"), std::string::npos);
}

TEST(Scene, EnvironmentOverridesAreNumbersOrCategoriesAndAllOrNothing) {
    ikebana::systems::insertion::Covariates env;
    env.category["humidity_pct"] = "high";
    ASSERT_TRUE(apply_environment_overrides(env, {"humidity_pct=70", "vase=metal"}));
    EXPECT_EQ(env.numeric.at("humidity_pct"), 70.0);
    EXPECT_FALSE(env.category.contains("humidity_pct")) << "a number replaces the earlier category";
    EXPECT_EQ(env.category.at("vase"), "metal");
    const auto before = env;
    const auto bad = apply_environment_overrides(env, {"room=dry", "no-equals-sign"});
    ASSERT_FALSE(bad);
    EXPECT_NE(bad.error().message.find("no-equals-sign"), std::string::npos);
    EXPECT_EQ(env.numeric, before.numeric);
    EXPECT_EQ(env.category, before.category) << "nothing half applied";
}
