#include <gtest/gtest.h>

#include <cmath>

#include "game/scene/scene.hpp"
#include "game/training/arrangement_score.hpp"

using namespace ikebana::game;

namespace {
SampleStem sample(const std::string& species, glm::dvec2 base, double angle_deg, double azimuth_deg, double height_m) {
    const double r = std::acos(-1.0) / 180.0;
    return {species, base, angle_deg * r, azimuth_deg * r, height_m};
}
// The stem the sample describes, exactly, from a kenzan at `origin`.
ArrangedStem stem_like(const SampleStem& s, const glm::dvec3& origin) {
    const glm::dvec3 dir{std::sin(s.angle_rad) * std::cos(s.azimuth_rad), std::sin(s.angle_rad) * std::sin(s.azimuth_rad), std::cos(s.angle_rad)};
    const glm::dvec3 base = origin + glm::dvec3(s.base_m, 0.0);
    return {s.species, base, base + dir * (s.height_m / dir.z), true, false};
}
} // namespace

TEST(ArrangementScore, TheSampleItselfScoresFullMarks) {
    const glm::dvec3 origin{0.0, 0.0, 0.008};
    const std::vector<SampleStem> s = {sample("sunflower", {0.0, -0.004}, 12, 200, 0.205), sample("cherry_branch", {0.012, 0.008}, 50, 30, 0.12)};
    const auto score = score_arrangement({stem_like(s[1], origin), stem_like(s[0], origin)}, s, origin);
    EXPECT_NEAR(score.score, 100.0, 1e-6);
    ASSERT_EQ(score.stems.size(), 2u);
    EXPECT_EQ(score.stems[0].arranged, 1u) << "matched by species, not by order";
    EXPECT_NEAR(score.stems[0].direction_error_deg, 0.0, 1e-6);
}

TEST(ArrangementScore, LargerDifferencesScoreLessAndAreNamed) {
    const glm::dvec3 origin{0.0};
    const std::vector<SampleStem> s = {sample("sunflower", {0.0, 0.0}, 20, 0, 0.2)};
    double previous = 101.0;
    for (double lean : {20.0, 25.0, 35.0, 50.0}) {
        auto arranged = stem_like(sample("sunflower", {0.0, 0.0}, lean, 0, 0.2), origin);
        const auto score = score_arrangement({arranged}, s, origin);
        EXPECT_LT(score.score, previous);
        EXPECT_NEAR(score.stems[0].direction_error_deg, lean - 20.0, 1e-4); // acos near 1 loses digits
        previous = score.score;
    }
    auto higher = stem_like(sample("sunflower", {0.004, 0.003}, 20, 0, 0.23), origin);
    const auto score = score_arrangement({higher}, s, origin);
    EXPECT_NEAR(score.stems[0].height_error_mm, 30.0, 1e-6);
    EXPECT_NEAR(score.stems[0].position_error_mm, 5.0, 1e-6);
    EXPECT_FALSE(score.lines().empty());
}

TEST(ArrangementScore, FallenAndMissingStemsScoreZero) {
    const glm::dvec3 origin{0.0};
    const std::vector<SampleStem> s = {sample("sunflower", {0.0, 0.0}, 10, 0, 0.2), sample("willow_branch", {0.0, 0.0}, 30, 90, 0.15)};
    auto fallen = stem_like(s[0], origin);
    fallen.fallen = true;
    fallen.in_kenzan = false;
    auto lying = stem_like(s[1], origin);
    lying.in_kenzan = false; // on the table: not part of the arrangement
    const auto score = score_arrangement({fallen, lying}, s, origin);
    EXPECT_EQ(score.stems[0].score, 0.0);
    EXPECT_EQ(score.stems[0].note, "fell");
    EXPECT_EQ(score.stems[1].note, "missing");
    EXPECT_EQ(score.score, 0.0);
}

TEST(Scene, SampleArrangementIsReadAndCheckedByPath) {
    const auto ok = parse_scene(R"({"format": "ikebana-scene/1", "kenzan": {"layout": "standard"},
        "sample": [{"species": "sunflower", "base_mm": [1, 2], "angle_deg": 30, "azimuth_deg": 90, "height_mm": 200}]})", "s.json");
    ASSERT_TRUE(ok) << ok.error().message;
    ASSERT_EQ(ok->sample.size(), 1u);
    EXPECT_NEAR(ok->sample[0].base_m.y, 0.002, 1e-12);
    EXPECT_NEAR(ok->sample[0].height_m, 0.2, 1e-12);
    const auto bad = parse_scene(R"({"format": "ikebana-scene/1", "kenzan": {"layout": "standard"},
        "sample": [{"species": "sunflower", "base_mm": [1, 2], "angle_deg": 120, "height_mm": 200}]})", "s.json");
    ASSERT_FALSE(bad);
    EXPECT_NE(bad.error().message.find("/sample/0/angle_deg"), std::string::npos) << bad.error().message;
}

TEST(Scene, DisplaySetsTheStereoModeAndTheRig) {
    const auto ok = parse_scene(R"({"format": "ikebana-scene/1", "kenzan": {"layout": "standard"},
        "display": {"stereo": "rows", "eye_separation_mm": 60, "screen_distance_mm": 500}})", "s.json");
    ASSERT_TRUE(ok) << ok.error().message;
    EXPECT_EQ(ok->display.stereo, "rows");
    EXPECT_NEAR(ok->display.eye_separation_m, 0.06, 1e-12);
    EXPECT_NEAR(ok->display.screen_distance_m, 0.5, 1e-12);
    const auto bad = parse_scene(R"({"format": "ikebana-scene/1", "kenzan": {"layout": "standard"}, "display": {"stereo": "hologram"}})", "s.json");
    ASSERT_FALSE(bad);
    EXPECT_NE(bad.error().message.find("/display/stereo"), std::string::npos) << bad.error().message;
}
