#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <optional>
#include <set>

#include <nlohmann/json.hpp>

#include "engine/assets/files.hpp"
#include "game/app/session_panel.hpp"
#include "game/kenzan/kenzan_layout.hpp"
#include "game/training/form_score.hpp"
#include "game/session/lesson_controls.hpp"
#include "game/session/lesson_demo.hpp"
#include "game/world/lesson_scene.hpp"
#include "game/session/lesson_session.hpp"
#include "game/session/session_timeline.hpp"
#include "game/session/window_state.hpp"
#include "game/world/world.hpp"
#include "systems/haptics/trainee_command_system.hpp"
#include "systems/presentation/draw_list.hpp"
#include "systems/presentation/frame_channel.hpp"
#include "components/hand.hpp"
#include "components/kenzan.hpp"
#include "components/stem.hpp"
#include "engine/devices/mouse_keyboard_device.hpp"
#include "engine/platform/pointer_input.hpp"
#include "engine/sched/clocks.hpp"
#include "../haptics/scripted_hands.hpp"
#include "game/lesson/form_table.hpp"
#include "game/lesson/lesson.hpp"
#include "game/lesson/role_colours.hpp"
#include "game/scene/scene.hpp"
#include "game/asset_paths.hpp"
#include "game/training/arrangement_score.hpp"

using namespace ikebana;
using namespace ikebana::game;
using namespace ikebana::components;

namespace {
constexpr double deg = 3.14159265358979323846 / 180.0;

KenzanFootprint footprint(const LessonDef& l) {
    const auto k = load_kenzan(l.kenzan_layout);
    EXPECT_TRUE(k.ok());
    return {{(k->columns + 1) * k->pitch_m, (k->rows + 1) * k->pitch_m}, k->base_thickness_m};
}

LessonDef lesson(const std::string& id) {
    auto l = load_lesson(id);
    EXPECT_TRUE(l.ok()) << (l.ok() ? "" : l.error().message);
    return l.ok() ? std::move(l).value() : LessonDef{};
}

ArrangementStem* stem_with_role(Arrangement& a, const std::string& role) {
    for (auto& s : a.stems) {
        if (s.role == role) return &s;
    }
    return nullptr;
}

const Criterion* criterion(const FormScore& f, const std::string& stem, const std::string& name) {
    for (const auto& c : f.criteria) {
        if (c.stem == stem && c.name == name) return &c;
    }
    return nullptr;
}

const RuleResult* rule(const FormScore& f, const std::string& name) {
    for (const auto& r : f.rules) {
        if (r.name == name) return &r;
    }
    return nullptr;
}

// A minimal valid form lesson's text, with `patch` applied to its JSON.
std::string lesson_text(const std::function<void(nlohmann::json&)>& patch = {}) {
    nlohmann::json j = nlohmann::json::parse(R"({
      "format": "ikebana-lesson/1", "id": "t", "title": "T", "school": "S", "source": "test",
      "container": {"shape": "round", "diameter_mm": 240, "depth_mm": 50},
      "kenzan": {"layout": "standard", "offset_mm": [-35, -35]},
      "materials": [{"species": "willow_branch"}, {"species": "chrysanthemum", "count": 2}],
      "main_stems": [
        {"role": "shin", "species": ["willow_branch"], "length": {"ratio": 1.2, "of": "container_size", "tolerance": 0.1},
         "tilt_deg": {"target": 15, "tolerance": 10}, "azimuth_deg": {"target": 45, "tolerance": 25}},
        {"role": "hikae", "length": {"ratio": 0.5, "of": "shin", "tolerance": 0.1}, "tilt_deg": {"target": 70, "tolerance": 10}}
      ]})");
    if (patch) patch(j);
    return j.dump();
}

std::filesystem::path write_temp(const std::string& name, const std::string& text) {
    const auto dir = std::filesystem::temp_directory_path() / "ikebana-lesson-test";
    std::filesystem::create_directories(dir);
    const auto path = dir / name;
    std::ofstream(path) << text;
    return path;
}
} // namespace

// A newcomer's start screen opens on a first lesson: the forms by level, free practice last.
TEST(LessonFile, ANewcomerIsOfferedAFirstLessonFirstAndFreePracticeLast) {
    auto lessons = load_shipped_lessons();
    ASSERT_TRUE(lessons.ok()) << lessons.error().message;
    order_for_newcomers(*lessons);
    ASSERT_GE(lessons->size(), 5u);
    EXPECT_EQ(lessons->front().id, "sogetsu_basic_upright");
    EXPECT_EQ(lessons->front().level, 1);
    EXPECT_EQ(lessons->back().id, "free_practice");
    for (std::size_t i = 1; i + 1 < lessons->size(); ++i) EXPECT_LE((*lessons)[i - 1].level, (*lessons)[i].level) << (*lessons)[i].id;
    const auto text = assets::read_text_file(asset_dir() / "lessons" / "sogetsu_basic_upright.json");
    ASSERT_TRUE(text.ok());
    std::string steep = *text;
    steep.replace(steep.find("\"level\": 1"), 10, "\"level\": 9");
    const auto refused = parse_lesson(steep, "steep.json");
    ASSERT_FALSE(refused.ok());
    EXPECT_NE(refused.error().message.find("steep.json"), std::string::npos);
    EXPECT_NE(refused.error().message.find("/level"), std::string::npos) << refused.error().message;
}

TEST(LessonFile, EveryShippedLessonLoadsWithWhatItNames) {
    const auto lessons = load_shipped_lessons();
    ASSERT_TRUE(lessons.ok()) << lessons.error().message;
    std::vector<std::string> ids;
    for (const auto& l : *lessons) ids.push_back(l.id);
    EXPECT_EQ(ids, (std::vector<std::string>{"free_practice", "ikenobo_shoka_shofutai", "ohara_rising_form", "sogetsu_basic_slanting", "sogetsu_basic_upright"}));
    for (const auto& l : *lessons) {
        EXPECT_FALSE(l.source.empty()) << l.id << " cites where its numbers come from";
        EXPECT_EQ(l.file.stem().string(), l.id) << "a lesson's file is named by its id";
    }
}

TEST(LessonFile, SogetsuUprightHasTheTextbooksProportionsAndAngles) {
    const LessonDef l = lesson("sogetsu_basic_upright");
    ASSERT_EQ(l.stems.size(), 3u);
    const double size = l.container.size_m();
    EXPECT_NEAR(nominal_length_m(l, 0), 1.5 * size, 1e-9);
    EXPECT_NEAR(nominal_length_m(l, 1), 0.75 * 1.5 * size, 1e-9);
    EXPECT_NEAR(nominal_length_m(l, 2), 0.75 * 0.75 * 1.5 * size, 1e-9);
    EXPECT_NEAR(l.stems[0].tilt_rad.target, 15 * deg, 1e-9);
    EXPECT_NEAR(l.stems[1].tilt_rad.target, 45 * deg, 1e-9);
    EXPECT_NEAR(l.stems[2].tilt_rad.target, 75 * deg, 1e-9);
    EXPECT_EQ(direction_words(l.stems[0].azimuth_rad->target), "left front");
    EXPECT_EQ(direction_words(l.stems[2].azimuth_rad->target), "right front");
    EXPECT_LT(l.kenzan_offset_m.x, 0.0) << "kenzan at the front left";
    EXPECT_LT(l.kenzan_offset_m.y, 0.0);
}

TEST(LessonFile, TheSlantingStyleExchangesShinAndSoesTilts) {
    const LessonDef up = lesson("sogetsu_basic_upright"), slant = lesson("sogetsu_basic_slanting");
    EXPECT_DOUBLE_EQ(slant.stems[0].tilt_rad.target, up.stems[1].tilt_rad.target);
    EXPECT_DOUBLE_EQ(slant.stems[1].tilt_rad.target, up.stems[0].tilt_rad.target);
    EXPECT_GT(slant.kenzan_offset_m.x, 0.0) << "kenzan at the back right";
    EXPECT_GT(slant.kenzan_offset_m.y, 0.0);
}

TEST(LessonFile, ABrokenLessonNamesEveryBadFieldByItsPath) {
    const auto r = parse_lesson(lesson_text([](nlohmann::json& j) {
                                    j["main_stems"][0]["tilt_deg"]["target"] = 120;
                                    j["main_stems"][1]["role"] = "shin";
                                    j["main_stems"][1]["length"]["of"] = "tai";
                                    j["container"]["shape"] = "bowl";
                                    j["rules"] = nlohmann::json::array({{{"rule", "no_crossing"}}});
                                    j["colour"] = "red";
                                }),
                                "broken.json");
    ASSERT_FALSE(r.ok());
    const std::string& m = r.error().message;
    EXPECT_NE(m.find("broken.json: /main_stems/0/tilt_deg/target: expected a number in [0, 90], got 120"), std::string::npos) << m;
    EXPECT_NE(m.find("broken.json: /main_stems/1/role: \"shin\" is already the role of /main_stems/0"), std::string::npos) << m;
    EXPECT_NE(m.find("/main_stems/1/length/of: expected \"container_size\", \"container_height\" or the role of an earlier main stem, got \"tai\""), std::string::npos) << m;
    EXPECT_NE(m.find("/container/shape"), std::string::npos) << m;
    EXPECT_NE(m.find("/rules/0/rule"), std::string::npos) << m;
    EXPECT_NE(m.find("/colour"), std::string::npos) << m;
}

TEST(LessonFile, ALengthCannotFollowALaterRole) {
    const auto r = parse_lesson(lesson_text([](nlohmann::json& j) { j["main_stems"][0]["length"]["of"] = "hikae"; }), "t.json");
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("t.json: /main_stems/0/length/of"), std::string::npos) << r.error().message;
}

TEST(LessonFile, IdsCannotReachOutsideTheAssetsFolder) {
    const auto r = parse_lesson(lesson_text([](nlohmann::json& j) {
                                    j["materials"][0]["species"] = "../../etc/passwd";
                                    j["kenzan"]["layout"] = "/dev/zero";
                                }),
                                "t.json");
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("t.json: /materials/0/species: expected a species id, got \"../../etc/passwd\""), std::string::npos) << r.error().message;
    EXPECT_NE(r.error().message.find("t.json: /kenzan/layout: expected a kenzan layout id"), std::string::npos) << r.error().message;
}

TEST(LessonFile, AKenzanThatDoesNotFitTheContainerIsRefused) {
    const auto path = write_temp("overhanging.json", lesson_text([](nlohmann::json& j) { j["kenzan"]["offset_mm"] = {-90, -40}; }));
    const auto r = load_lesson_file(path);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("overhanging.json: /kenzan: the 84 x 84 mm kenzan at [-90, -40] mm does not fit inside the container"), std::string::npos)
        << r.error().message;
}

TEST(LessonFile, AFormNoMaterialCanMakeIsRefusedNamingTheStem) {
    // 2.0 x 290 mm = 580 mm of shin; the willow is 450 mm.
    const auto path = write_temp("too_tall.json", lesson_text([](nlohmann::json& j) { j["main_stems"][0]["length"]["ratio"] = 2.0; }));
    const auto r = load_lesson_file(path);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("too_tall.json: /main_stems/0: shin wants 580 mm above the kenzan (and 13 mm in its pins) but its longest material is 450 mm"),
              std::string::npos)
        << r.error().message;
}

TEST(LessonFile, AMaterialOfAnUnknownSpeciesIsNamed) {
    const auto path = write_temp("unknown.json", lesson_text([](nlohmann::json& j) { j["materials"][1]["species"] = "tulip"; }));
    const auto r = load_lesson_file(path);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("unknown.json: /materials/1/species: no species \"tulip\""), std::string::npos) << r.error().message;
}

TEST(FormScore, EveryShippedFormsModelArrangementScoresAtLeast90) {
    for (const char* id : {"sogetsu_basic_upright", "sogetsu_basic_slanting", "ohara_rising_form", "ikenobo_shoka_shofutai"}) {
        const LessonDef l = lesson(id);
        const auto scored = score_form(l, model_arrangement(l, footprint(l)), footprint(l));
        ASSERT_TRUE(scored.ok()) << scored.error().message;
        EXPECT_GE(scored->score, 90.0) << id;
        for (const auto& r : scored->rules) EXPECT_TRUE(r.ok) << id << ": " << r.tip;
    }
}

// A first-time trainee pressed Enter before placing anything and was given 14 points: the rules an
// empty kenzan "met" (no stems cross, no leaves in the water). Nothing standing scores nothing, and
// each rule says why; a fallen stem alone does not stand either.
TEST(FormScore, NothingStandingInTheKenzanScoresNothing) {
    for (const char* id : {"sogetsu_basic_upright", "sogetsu_basic_slanting", "ohara_rising_form", "ikenobo_shoka_shofutai"}) {
        const LessonDef l = lesson(id);
        Arrangement empty;
        const auto scored = score_form(l, empty, footprint(l));
        ASSERT_TRUE(scored.ok()) << scored.error().message;
        EXPECT_EQ(scored->score, 0.0) << id;
        for (const auto& r : scored->rules) EXPECT_EQ(r.tip, "nothing stands in the kenzan yet") << id;
        Arrangement fallen = model_arrangement(l, footprint(l));
        fallen.stems.resize(1);
        fallen.stems[0].standing = false;
        EXPECT_EQ(score_form(l, fallen, footprint(l))->score, 0.0) << id;
    }
}

TEST(FormScore, ShinLeftAt45DegreesLosesPointsOnShinsTiltWithATipNamingShin) {
    const LessonDef l = lesson("sogetsu_basic_upright");
    Arrangement a = model_arrangement(l, footprint(l));
    const double full = score_form(l, a, footprint(l))->score;
    stem_with_role(a, "shin")->tilt_rad = 45 * deg;
    const auto scored = score_form(l, a, footprint(l));
    ASSERT_TRUE(scored.ok());
    EXPECT_LT(scored->score, full);
    EXPECT_LT(scored->score, 90.0) << "a shin at 45 degrees is the slanting style, not this one";
    const Criterion* tilt = criterion(*scored, "shin", "tilt_deg");
    ASSERT_NE(tilt, nullptr);
    EXPECT_DOUBLE_EQ(tilt->points, 0.0) << "30 degrees off a band of 10 is three bands";
    EXPECT_EQ(tilt->tip, "shin: 45° from vertical, the form wants 15° ±10°, 20° outside it: raise it 30° toward upright");
    for (const auto& c : scored->criteria) {
        if (c.stem != "shin" || c.name != "tilt_deg") {
            EXPECT_EQ(c.points, c.max_points) << c.tip;
        }
    }
}

TEST(FormScore, AStemTooUprightIsToldToTiltTowardTheFormsDirection) {
    const LessonDef l = lesson("sogetsu_basic_upright");
    Arrangement a = model_arrangement(l, footprint(l));
    stem_with_role(a, "soe")->tilt_rad = 28 * deg;
    const auto scored = score_form(l, a, footprint(l));
    const Criterion* tilt = criterion(*scored, "soe", "tilt_deg");
    ASSERT_NE(tilt, nullptr);
    EXPECT_EQ(tilt->tip, "soe: 28° from vertical, the form wants 45° ±10°, 7° outside it: lean it 17° more toward the left front");
    EXPECT_NEAR(tilt->points, 14.0 * 0.3 * (1.0 - 7.0 / 10.0), 1e-9) << "7 degrees beyond the band of 10: 30 % at its edge, 70 % of the way to nothing";
}

// Issue 41: a school's band is strict. Within it every point; just outside, 30 %; one band further, none
// (soe at 58 degrees for 45 +-10 earned 12.2 of 14 when points fell to nothing only at three bands).
TEST(FormScore, OutsideItsBandACriterionEarnsLittleAndNothingOneBandFurther) {
    EXPECT_DOUBLE_EQ(band_points(10, 10, 8), 8);
    EXPECT_NEAR(band_points(10.001, 10, 8), 8 * 0.3, 1e-3);
    EXPECT_DOUBLE_EQ(band_points(-15, 10, 8), 8 * 0.3 * 0.5);
    EXPECT_DOUBLE_EQ(band_points(20, 10, 8), 0);
    EXPECT_DOUBLE_EQ(band_points(300, 10, 8), 0);
    EXPECT_DOUBLE_EQ(band_points(2, 0, 3), 3 * 0.3 * 0.5) << "a band of 0 counts as a pin pitch, 4";
    EXPECT_NEAR(band_points(13, 10, 14), 2.94, 1e-9) << "soe at 58 for 45 +-10";
    // A base off its part of the kenzan is a near miss: all points at the edge, none two pitches out.
    EXPECT_DOUBLE_EQ(position_points(0, 3), 3);
    EXPECT_DOUBLE_EQ(position_points(4, 3), 1.5);
    EXPECT_DOUBLE_EQ(position_points(9, 3), 0);
}

TEST(FormScore, RolesGoToTheStemsThatFitThemWhateverTheirOrder) {
    const LessonDef l = lesson("sogetsu_basic_upright");
    Arrangement a = model_arrangement(l, footprint(l));
    std::reverse(a.stems.begin(), a.stems.end());
    for (auto& s : a.stems) s.role.clear();
    // A supporting chrysanthemum beside hikae's.
    a.stems.push_back({"", "chrysanthemum", {0.01, -0.03}, 0.1, 70 * deg, 0.0, true, {}, {}});
    const auto scored = score_form(l, a, footprint(l));
    ASSERT_TRUE(scored.ok());
    const auto& stems = scored->arrangement.stems;
    // The model's two supporting stems (the jushi that hide the kenzan) came last, so first now.
    ASSERT_EQ(stems.size(), 6u);
    EXPECT_EQ(stems[0].role, "supporting");
    EXPECT_EQ(stems[1].role, "supporting");
    EXPECT_EQ(stems[2].role, "hikae");
    EXPECT_EQ(stems[3].role, "soe");
    EXPECT_EQ(stems[4].role, "shin");
    EXPECT_EQ(stems[5].role, "supporting");
    EXPECT_GE(scored->score, 90.0);
}

TEST(FormScore, AFallenStemEarnsNothingAndTheTipSaysItFell) {
    const LessonDef l = lesson("sogetsu_basic_upright");
    Arrangement a = model_arrangement(l, footprint(l));
    stem_with_role(a, "hikae")->standing = false;
    const auto scored = score_form(l, a, footprint(l));
    ASSERT_TRUE(scored.ok());
    for (const auto& c : scored->criteria) {
        if (c.stem == "hikae") {
            EXPECT_EQ(c.points, 0.0) << c.name;
            EXPECT_EQ(c.tip.rfind("hikae: it fell", 0), 0u) << c.tip;
        }
    }
    const RuleResult* odd = rule(*scored, "odd_main_stems");
    ASSERT_NE(odd, nullptr);
    EXPECT_FALSE(odd->ok);
    EXPECT_EQ(odd->tip, "2 main stems stand; the form wants an odd number: add hikae");
}

TEST(FormScore, AMissingRoleIsNamedWithTheLengthToCutItTo) {
    const LessonDef l = lesson("sogetsu_basic_upright");
    Arrangement a = model_arrangement(l, footprint(l));
    a.stems.erase(a.stems.begin()); // shin
    const auto scored = score_form(l, a, footprint(l));
    const Criterion* length = criterion(*scored, "shin", "length_mm");
    ASSERT_NE(length, nullptr);
    EXPECT_FALSE(length->measured.has_value());
    EXPECT_EQ(length->tip, "shin: no stem plays it: choose a material for it and cut it to 435 mm above the kenzan");
}

TEST(FormScore, CrossingStemsAndACentredKenzanBreakTheirRules) {
    const LessonDef l = lesson("sogetsu_basic_upright");
    Arrangement a = model_arrangement(l, footprint(l));
    // Hikae from the right of the kenzan leaning left, 30 degrees: it crosses shin 131 mm up in the front view.
    auto* hikae = stem_with_role(a, "hikae");
    hikae->base_m = {0.03, -0.02};
    hikae->tilt_rad = 30 * deg;
    hikae->azimuth_rad = 90 * deg;
    a.kenzan_offset_m = glm::dvec2{0.005, 0.0};
    const auto scored = score_form(l, a, footprint(l));
    const RuleResult* crossing = rule(*scored, "no_crossing_front");
    ASSERT_NE(crossing, nullptr);
    EXPECT_FALSE(crossing->ok);
    EXPECT_EQ(crossing->tip, "shin and hikae cross in the front view, 131 mm above the kenzan: move one base across, or turn one the other way");
    const RuleResult* centre = rule(*scored, "kenzan_off_centre");
    EXPECT_FALSE(centre->ok);
    EXPECT_EQ(centre->tip, "the kenzan sits in the container's centre (5 mm from it): move it toward a side, leaving open water");
}

// Leaves under the water rot: a standing stem with leaves below the water line breaks the rule, and its
// tip names the stem (role and species) and how many; two stems of one name are said once. Leaves above
// it, or none known, keep it.
TEST(FormScore, LeavesUnderTheWaterAreNamedByTheStemTheyGrowOn) {
    const LessonDef l = lesson("sogetsu_basic_upright");
    Arrangement a = model_arrangement(l, footprint(l));
    const double water = water_level_m(l, footprint(l));
    ASSERT_GT(water, 0.0) << "a suiban's water stands above the kenzan's plate";
    stem_with_role(a, "hikae")->leaf_heights_m = {water + 0.02, water + 0.05};
    const auto dry = score_form(l, a, footprint(l));
    ASSERT_TRUE(dry.ok());
    const RuleResult* leaves = rule(*dry, "no_leaves_under_water");
    ASSERT_NE(leaves, nullptr);
    EXPECT_TRUE(leaves->ok) << leaves->tip;
    EXPECT_EQ(leaves->tip, "no leaves under the water");
    stem_with_role(a, "hikae")->leaf_heights_m = {water - 0.005, water - 0.001, water + 0.02};
    a.stems.push_back({"supporting", "chrysanthemum", {0.01, -0.03}, 0.05, 60 * deg, 0.0, true, {}, {water - 0.002}});
    a.stems.push_back({"supporting", "chrysanthemum", {-0.01, -0.03}, 0.05, 60 * deg, 0.0, true, {}, {water - 0.002, water - 0.003}});
    const auto wet = score_form(l, a, footprint(l));
    ASSERT_TRUE(wet.ok());
    leaves = rule(*wet, "no_leaves_under_water");
    ASSERT_NE(leaves, nullptr);
    EXPECT_FALSE(leaves->ok);
    EXPECT_EQ(leaves->tip, "hikae (chrysanthemum) has 2 leaves; 2 stems of supporting (chrysanthemum) have 3 leaves under the water: strip them (P with the "
                           "cube on each leaf), they rot in the water");
    EXPECT_LT(wet->score, dry->score) << "the rule's points are lost";
    // Read back from the result's JSON: the leaves' heights go with it.
    auto again = parse_arrangement(wet->json(), "result.json");
    ASSERT_TRUE(again.ok()) << again.error().message;
    EXPECT_EQ(stem_with_role(*again, "hikae")->leaf_heights_m.size(), 3u);
    const auto bad = parse_arrangement(R"({"stems": [{"species": "iris", "base_mm": [0, 0], "length_mm": 50, "tilt_deg": 0, "azimuth_deg": 0,
                                          "leaf_heights_mm": [12, "low"]}]})",
                                       "a.json");
    ASSERT_FALSE(bad.ok());
    EXPECT_NE(bad.error().message.find("a.json: /stems/0/leaf_heights_mm/1: expected a height within 3000 mm, got \"low\""), std::string::npos)
        << bad.error().message;
}

TEST(FormScore, AKenzanSeenFromTheFrontIsNamedWithWhereItShows) {
    const LessonDef l = lesson("ohara_rising_form");
    Arrangement a = model_arrangement(l, footprint(l));
    std::erase_if(a.stems, [](const ArrangementStem& s) { return s.role == "supporting"; });
    const auto scored = score_form(l, a, footprint(l));
    const RuleResult* hidden = rule(*scored, "kenzan_hidden_front");
    ASSERT_NE(hidden, nullptr);
    EXPECT_FALSE(hidden->ok);
    EXPECT_NE(hidden->tip.find("the kenzan still shows from the front: the supporting stems hide "), std::string::npos) << hidden->tip;
    EXPECT_NE(hidden->tip.find("the form wants 80 %: add a low supporting stem leaning toward the viewer, "), std::string::npos) << hidden->tip;
    // Where, in words a beginner can see: never coordinates.
    EXPECT_EQ(hidden->tip.find("x ="), std::string::npos) << hidden->tip;
    EXPECT_EQ(hidden->tip.find(" mm"), std::string::npos) << hidden->tip;
    const bool placed = hidden->tip.ends_with("in front of its left end") || hidden->tip.ends_with("in front of its middle") ||
                        hidden->tip.ends_with("in front of its right end") || hidden->tip.ends_with("across most of its width");
    EXPECT_TRUE(placed) << hidden->tip;
    EXPECT_DOUBLE_EQ(hidden->points, 0.0);
}

TEST(FormScore, StraightStemsDoNotRiseAsOneLineFromTheWater) {
    const LessonDef l = lesson("ikenobo_shoka_shofutai");
    Arrangement a = model_arrangement(l, footprint(l));
    for (auto& s : a.stems) s.path_m.clear();
    const auto scored = score_form(l, a, footprint(l));
    const RuleResult* line = rule(*scored, "one_line_at_water");
    ASSERT_NE(line, nullptr);
    EXPECT_FALSE(line->ok);
    EXPECT_NE(line->tip.find("the form keeps them one line for 60-80 mm before they spread"), std::string::npos) << line->tip;
}

// The model's one-line stems stand on the pin rows of a 3 x 3 block at the kenzan's centre, placed so
// that their lines, once parted (each its way at its rate), stay closer together than in a plain row,
// and never pass through each other on the way up.
TEST(ModelArrangement, OneLineStemsStandCloseSoThatTheirLinesPartLateAndNeverThroughEachOther) {
    const LessonDef l = lesson("ikenobo_shoka_shofutai");
    Arrangement a = model_arrangement(l, footprint(l));
    ASSERT_EQ(a.stems.size(), 3u);
    std::vector<glm::dvec2> ways;
    for (std::size_t i = 0; i < a.stems.size(); ++i) {
        const auto& s = a.stems[i];
        ASSERT_EQ(s.path_m.size(), 2u) << s.role;
        EXPECT_NEAR(s.path_m[0].x, s.base_m.x, 1e-12) << s.role << ": its rise starts over its base";
        EXPECT_NEAR(s.path_m[0].y, s.base_m.y, 1e-12) << s.role;
        EXPECT_LE(std::max(std::abs(s.base_m.x), std::abs(s.base_m.y)), 0.004 + 1e-12) << s.role << ": within a pin row of the centre";
        const glm::dvec3 d = glm::normalize(s.path_m[1] - s.path_m[0]);
        ways.push_back(glm::dvec2{d.x, d.y} / d.z);
    }
    const auto widest = [&](const std::vector<glm::dvec2>& bases, double z) {
        double w = 0.0;
        for (std::size_t i = 0; i < bases.size(); ++i) {
            for (std::size_t j = i + 1; j < bases.size(); ++j) w = std::max(w, glm::length(bases[i] + z * ways[i] - bases[j] - z * ways[j]));
        }
        return w;
    };
    std::vector<glm::dvec2> bases, row;
    for (std::size_t i = 0; i < a.stems.size(); ++i) {
        bases.push_back(a.stems[i].base_m);
        row.push_back({(static_cast<double>(i) - 1.0) * 0.004, 0.0});
    }
    EXPECT_LT(widest(bases, 0.02), widest(row, 0.02)) << "parted 20 mm up, closer than a row of three";
    for (std::size_t i = 0; i < bases.size(); ++i) {
        for (std::size_t j = i + 1; j < bases.size(); ++j) {
            for (int mm = 0; mm <= 60; ++mm) {
                const double z = mm * 1e-3;
                EXPECT_GE(glm::length(bases[i] + z * ways[i] - bases[j] - z * ways[j]), 0.0036) << a.stems[i].role << " and " << a.stems[j].role << " at " << mm << " mm";
            }
        }
    }
    const auto scored = score_form(l, a, footprint(l));
    ASSERT_TRUE(scored.ok());
    const RuleResult* line = rule(*scored, "one_line_at_water");
    ASSERT_NE(line, nullptr);
    EXPECT_TRUE(line->ok) << line->tip;
}

TEST(FormScore, ARoleNotInTheLessonOrGivenTwiceIsRefusedByField) {
    const LessonDef l = lesson("sogetsu_basic_upright");
    Arrangement a = model_arrangement(l, footprint(l));
    a.stems[1].role = "tai";
    auto r = score_form(l, a, footprint(l), "mine.json");
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().message, "mine.json: /stems/1/role: \"tai\" is not a role of sogetsu_basic_upright (shin, soe, hikae, or supporting)");
    a.stems[1].role = "shin";
    r = score_form(l, a, footprint(l), "mine.json");
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().message, "mine.json: /stems/1/role: \"shin\" is already played by /stems/0");
}

TEST(Arrangement, AResultReadBackIsItsArrangementAndScoresTheSame) {
    const LessonDef l = lesson("ikenobo_shoka_shofutai");
    Arrangement a = model_arrangement(l, footprint(l));
    stem_with_role(a, "soe")->tilt_rad = 50 * deg;
    const auto first = score_form(l, a, footprint(l));
    ASSERT_TRUE(first.ok());
    const auto again = parse_arrangement(first->json(), "result.json");
    ASSERT_TRUE(again.ok()) << again.error().message;
    ASSERT_EQ(again->stems.size(), a.stems.size());
    EXPECT_EQ(again->stems[0].path_m.size(), a.stems[0].path_m.size());
    const auto second = score_form(l, *again, footprint(l));
    ASSERT_TRUE(second.ok());
    EXPECT_NEAR(second->score, first->score, 0.1);
    EXPECT_EQ(second->json(), first->json());
}

TEST(Arrangement, BadFieldsAreNamedAndNothingIsHalfRead) {
    const auto r = parse_arrangement(R"({"stems": [{"species": "sunflower", "base_mm": [0], "length_mm": -5, "tilt_deg": 30, "azimuth_deg": 0,
                                        "path_mm": [[0, 0, "x"]]}, 7], "extra": 1})",
                                     "a.json");
    ASSERT_FALSE(r.ok());
    const std::string& m = r.error().message;
    EXPECT_NE(m.find("a.json: /stems/0/base_mm: expected at least 2 numbers, got 1"), std::string::npos) << m;
    EXPECT_NE(m.find("a.json: /stems/0/length_mm"), std::string::npos) << m;
    EXPECT_NE(m.find("a.json: /stems/0/path_mm/0: expected [x, y, z] in mm"), std::string::npos) << m;
    EXPECT_NE(m.find("a.json: /stems/1: expected an object, got 7"), std::string::npos) << m;
    EXPECT_NE(m.find("a.json: /extra"), std::string::npos) << m;
}

TEST(FormScore, FreePracticeIsScoredAgainstItsSceneAsTheSampleComparisonDoes) {
    const LessonDef l = lesson("free_practice");
    const auto scene = load_scene(asset_path(l.scene));
    ASSERT_TRUE(scene.ok());
    Arrangement a;
    // The sample's own stems, as an arrangement (its azimuth is from +x toward +y; the lesson's from the front).
    for (const auto& s : scene->sample) {
        const glm::dvec3 dir{std::sin(s.angle_rad) * std::cos(s.azimuth_rad), std::sin(s.angle_rad) * std::sin(s.azimuth_rad), std::cos(s.angle_rad)};
        a.stems.push_back({"", s.species, s.base_m, s.height_m / dir.z, s.angle_rad, std::atan2(-dir.x, -dir.y), true, {}, {}});
    }
    const FormScore f = score_sample(l, a, scene->sample);
    EXPECT_NEAR(f.score, 100.0, 1e-6);
    a.stems[0].tilt_rad += 20 * deg;
    const FormScore worse = score_sample(l, a, scene->sample);
    EXPECT_LT(worse.score, 90.0);
    double points = 0.0;
    for (const auto& c : worse.criteria) points += c.points;
    EXPECT_NEAR(points, worse.score, 1e-9) << "the criteria's points add up to the score";
}

// The teacher's demonstration goes through the hands: grab, cut, (bend), turn, push, let go; what the
// physics leaves is measured and scored.
TEST(LessonDemo, TheOharaDemoStandsSubjectAndObjectThroughTheHandAndScoresThem) {
    const LessonDef l = lesson("ohara_rising_form");
    const auto demo = run_lesson_demo(l);
    ASSERT_TRUE(demo.ok()) << demo.error().message;
    bool cut = false;
    for (const auto& step : demo->steps) cut = cut || step.what.find("subject: cut it to 438 mm") != std::string::npos;
    EXPECT_TRUE(cut) << "the willow was cut to the subject's length through the cutting system";
    for (const char* role : {"subject", "object"}) {
        double points = 0.0, max_points = 0.0;
        for (const auto& c : demo->score.criteria) {
            if (c.stem != role) continue;
            points += c.points;
            max_points += c.max_points;
            EXPECT_GT(c.points, 0.0) << c.tip;
        }
        EXPECT_GE(points, 0.9 * max_points) << role;
    }
    // The measured arrangement is what `lesson score --arrangement` reads, and scores the same.
    const auto again = parse_arrangement(demo->score.json(), "demo.json");
    ASSERT_TRUE(again.ok()) << again.error().message;
    const auto rescored = score_form(l, *again, footprint(l));
    ASSERT_TRUE(rescored.ok());
    EXPECT_NEAR(rescored->score, demo->score.score, 0.5);
    EXPECT_GE(demo->score.score, 90.0);
}

namespace {
// Every criterion of every main stem earns all its points. Sogetsu's hikae (a 245 mm chrysanthemum, 75
// +-10) included: its line from a front-left kenzan meets the suiban's wall 42 mm up, so the teacher
// holds it at 68, where it passes just over the rim, and it settles at about 70 (issue 41; before the
// rim held stems up, held at 60 it settled at 62, and held over the rim it tore out).
void expect_every_criterion_met(const FormScore& score, const std::string& why) {
    for (const auto& c : score.criteria) {
        EXPECT_DOUBLE_EQ(c.points, c.max_points) << c.stem << " " << c.name << ": " << c.tip << "\n" << why;
        if (c.stem == "hikae" && c.name == "tilt_deg") {
            ASSERT_TRUE(c.measured.has_value()) << why;
            EXPECT_GE(*c.measured, 65.0) << "within the form's band\n" << why;
        }
    }
}
} // namespace

TEST(LessonDemo, TheSogetsuBasicUprightDemoStandsItsStemsAndJushiAndHidesTheKenzan) {
    const LessonDef l = lesson("sogetsu_basic_upright");
    const auto demo = run_lesson_demo(l);
    ASSERT_TRUE(demo.ok()) << demo.error().message;
    std::size_t standing = 0;
    for (const auto& s : demo->score.arrangement.stems) standing += s.standing ? 1 : 0;
    std::string why;
    for (const auto& line : demo->score.lines()) why += line + "\n";
    EXPECT_EQ(standing, 5u) << "shin (a willow), soe (a cherry branch at 45 degrees), hikae (a chrysanthemum, low) and two jushi\n" << why;
    expect_every_criterion_met(demo->score, why);
    for (const auto& r : demo->score.rules) EXPECT_TRUE(r.ok) << r.tip << "\n" << why;
    EXPECT_GE(demo->score.score, 99.5) << why;
}

// What the Ikenobo demonstrations show, whatever works the hands: soe and tai bent (shin not), no stem
// missed or taken again, all three standing, the one-line rule kept and at least 90 points.
namespace {
void expect_shoka_bent_as_one_line(const DemoResult& demo) {
    std::string steps;
    for (const auto& s : demo.steps) steps += s.what + "\n";
    // Said once the right hand holds it below a bend that was made.
    for (const char* bent : {"soe: hold it upright below the bend", "tai: hold it upright below the bend"}) EXPECT_NE(steps.find(bent), std::string::npos) << steps;

    EXPECT_EQ(steps.find("shin: bend it"), std::string::npos) << steps;
    EXPECT_EQ(steps.find("missed"), std::string::npos) << steps;
    EXPECT_EQ(steps.find("take it again"), std::string::npos) << steps;
    std::size_t standing = 0;
    for (const auto& s : demo.score.arrangement.stems) standing += s.standing ? 1 : 0;
    EXPECT_EQ(standing, 3u);
    const RuleResult* line = rule(demo.score, "one_line_at_water");
    ASSERT_NE(line, nullptr);
    EXPECT_TRUE(line->ok) << line->tip;
    std::string why;
    for (const auto& text : demo.score.lines()) why += text + "\n";
    EXPECT_GE(demo.score.score, 90.0) << why;
}
} // namespace

// Ikenobo's shoka: the stems leave the water as one line for 60-80 mm and then part. Soe and tai are
// laid on the table and bent there (through the mouse, held up: it cannot turn a stem about its axis) (the two-hand bend: the left hand joins the right, its wrist rolls
// against it), lifted, turned about their own axes until the part above the bend leans the role's way
// (a bend keeps its side of the bark), held upright below the bend and pushed in; shin leans on its own
// curve. Straight, the same stems part at the water (FormScore.StraightStemsDoNotRiseAsOneLineFromTheWater)
// and score 89. Every criterion of the two bent roles is within its band. One demonstration for both (it is
// the suite's dearest: it ran twice).
TEST(LessonDemo, TheShokaDemoBendsSoeAndTaiSoThatTheStemsRiseAsOneLineTheWayTheirRolesWant) {
    const LessonDef l = lesson("ikenobo_shoka_shofutai");
    const auto demo = run_lesson_demo(l);
    ASSERT_TRUE(demo.ok()) << demo.error().message;
    expect_shoka_bent_as_one_line(*demo);
    // With the hands' devices, bent lying on the table, then carried bent to the kenzan.
    std::string steps;
    for (const auto& s : demo->steps) steps += s.what + "\n";
    for (const char* on_table : {"soe: lay it on the table to bend it", "tai: lay it on the table to bend it"}) EXPECT_NE(steps.find(on_table), std::string::npos) << steps;
    std::size_t judged = 0;
    for (const auto& c : demo->score.criteria) {
        if (c.stem == "soe" || c.stem == "tai") {
            ++judged;
            EXPECT_DOUBLE_EQ(c.points, c.max_points) << c.tip;
        }
    }
    EXPECT_EQ(judged, 6u) << "length, tilt and direction of each";
    // Grabs, cuts, two-hand bends, insertions and releases: every system met what it handles, so every
    // declared access was used, but one only a failing device uses (ForceSafety.WritesThatKeepFailing...
    // shows hand_force writing it).
    std::string unused;
    for (const auto& line : demo->unused_access) unused += line + "\n";
    EXPECT_EQ(unused, "system 'hand_force' declares writing 'systems::HandLinks' and never touches it\n");
}

namespace {
struct LessonPointer : platform::PointerSource {
    platform::PointerState state = [] {
        platform::PointerState s;
        s.cursor_px = {600.0, 337.0};
        s.window_px = {1200.0, 675.0};
        return s;
    }();
    platform::PointerState read() override { return state; }
};
} // namespace

// The mouse in a lesson, as the window drives it: take the willow, cut it for shin, Ctrl+drag it
// upright; the stem turns with the hand.
TEST(LessonWithTheMouse, CtrlDragTiltsTheHeldStemUpright) {
    const LessonDef l = lesson("sogetsu_basic_upright");
    auto scene = scene_for_lesson(l);
    ASSERT_TRUE(scene.ok());
    auto world = World::create(*scene);
    ASSERT_TRUE(world.ok()) << world.error().message;
    World& w = **world;
    LessonPointer pointer;
    devices::MouseKeyboardHands::Config config;
    config.workspace_width_m = 0.7;
    config.workspace_height_m = 0.6;
    config.reach_min_m = {-0.45, -0.5, 0.0};
    config.reach_max_m = {0.45, 0.4, 0.6};
    devices::MouseKeyboardHands mouse(pointer, config);
    for (const auto& h : scene->hands) mouse.place(h.hand, h.position_m);
    w.attach_device(0, mouse.hand(0));
    w.attach_device(1, mouse.hand(1));
    sched::DeterministicClock clock(w.schedule);
    const auto willow = w.flowers[0].entity;
    ASSERT_EQ(w.flowers[0].species, "willow_branch");
    const auto& x = w.sim.get<StemPoints>(willow).position_m;
    clock.run_for_us(300'000);
    // The hand onto the willow, 60 mm from its bottom end, in frame-sized steps.
    const glm::dvec3 hand = w.sim.get<HandProxy>(w.hands[1]).position_m;
    const glm::dvec3 target = x.front() + glm::normalize(x.back() - x.front()) * 0.062;
    auto& s = pointer.state;
    const auto frames = [&](int n, glm::dvec2 per_frame_px, bool depth) {
        for (int i = 0; i < n; ++i) {
            s.cursor_px += per_frame_px;
            s.depth_modifier = depth;
            clock.run_for_us(33'333);
        }
        s.depth_modifier = false;
    };
    const double px_per_m_x = 1200.0 / 0.7, px_per_m_y = 675.0 / 0.6;
    frames(10, {(target.x - hand.x) * px_per_m_x / 10, 0.0}, false);
    frames(10, {0.0, -(target.y - hand.y) * px_per_m_y / 10}, true);
    frames(10, {0.0, -(target.z - hand.z) * px_per_m_y / 10}, false);
    s.grab_button = true;
    frames(3, {0, 0}, false);
    ASSERT_EQ(test::hand_view(w, 1).held, willow) << "one press took it";
    frames(10, {0.0, -0.2 * px_per_m_y / 10}, false); // lift 200 mm
    ASSERT_TRUE(w.trainee.push({systems::TraineeCommand::Kind::cut, 1, 0.448}));
    frames(3, {0, 0}, false);
    double length = 0.0;
    for (const double l_m : w.sim.get<StemRestShape>(willow).segment_length_m) length += l_m;
    EXPECT_NEAR(length, 0.448, 1e-6) << "cut for shin";
    const double lying = std::acos(glm::normalize(x.back() - x.front()).z);
    s.tilt_modifier = true;
    frames(20, {-18.0, 0.0}, false); // 360 px left: a quarter turn at a quarter degree a pixel, its top up
    s.tilt_modifier = false;
    frames(30, {0, 0}, false);
    const double now = std::acos(glm::normalize(x.back() - x.front()).z);
    EXPECT_GT(lying, 75 * deg);
    EXPECT_LT(now, 25 * deg) << "Ctrl+drag stood it up";
}

// The Sogetsu lesson through the mouse, as the window reads it: the same MouseKeyboardHands and the
// same lesson keys (C cuts for the role, Enter scores), in whole pixels and wheel clicks, one motion
// per reading. Not a device: the hand is wherever the mouse took it.
TEST(LessonWithTheMouse, TheSogetsuBasicUprightLessonThroughTheMouseMeetsEveryBandAndRuleAsTheDevicesDo) {
    const LessonDef l = lesson("sogetsu_basic_upright");
    DemoOptions options;
    options.through_mouse = true;
    const auto session = run_lesson_demo(l, options);
    ASSERT_TRUE(session.ok()) << session.error().message;
    std::string steps;
    for (const auto& s : session->steps) steps += s.what + "\n";
    // (Hikae: 245 mm above the kenzan and 35 in the pins at the 69° the suiban's rim lets it lean.)
    for (const char* cut : {"shin: cut it to 448 mm", "soe: cut it to 345 mm", "hikae: cut it to 279 mm"}) EXPECT_NE(steps.find(cut), std::string::npos) << cut;
    EXPECT_EQ(steps.find("it was cut to"), std::string::npos) << "C cut each to what its role wants:\n" << steps;
    EXPECT_EQ(steps.find("missed"), std::string::npos) << steps;
    std::string why;
    for (const auto& line : session->score.lines()) why += line + "\n";
    expect_every_criterion_met(session->score, why);
    for (const auto& r : session->score.rules) EXPECT_TRUE(r.ok) << r.tip << "\n" << why;
    EXPECT_GE(session->score.score, 99.5) << why;
}

// With a mouse the other hand is Tab away, and the button goes with the mouse as it is: the left hand
// takes the stem beside the right, the wrist rolls with Ctrl held, and the right takes it again below
// the bend, as a trainee would.
TEST(LessonWithTheMouse, TheShokaLessonThroughTheMouseBendsWithBothHandsAndScoresNinety) {
    const LessonDef l = lesson("ikenobo_shoka_shofutai");
    DemoOptions options;
    options.through_mouse = true;
    const auto session = run_lesson_demo(l, options);
    ASSERT_TRUE(session.ok()) << session.error().message;
    expect_shoka_bent_as_one_line(*session);
}

TEST(LessonWithTheMouse, ShinLeftAtFortyFiveLosesPointsOnShinsTiltWithATipNamingShin) {
    const LessonDef l = lesson("sogetsu_basic_upright");
    DemoOptions options;
    options.through_mouse = true;
    options.tilt_deg["shin"] = 45.0;
    const auto session = run_lesson_demo(l, options);
    ASSERT_TRUE(session.ok()) << session.error().message;
    EXPECT_LT(session->score.score, 90.0);
    bool shin_tilt_lost = false;
    for (const auto& c : session->score.criteria) {
        if (c.stem == "shin" && c.name == "tilt_deg") {
            shin_tilt_lost = c.points < 0.5 * c.max_points;
            EXPECT_NE(c.tip.find("shin"), std::string::npos) << c.tip;
            ASSERT_TRUE(c.measured.has_value());
            EXPECT_NEAR(*c.measured, 45.0, 8.0);
        } else if (c.name == "tilt_deg") {
            EXPECT_GE(c.points, 0.8 * c.max_points) << c.stem << ": only shin was held wrong; " << c.tip;
        }
    }
    EXPECT_TRUE(shin_tilt_lost);
}

// The keys the window and the scripted mouse share act once per press: R asks once to start over, G
// turns the targets on and off, Enter scores, C with nothing in the hand cuts nothing.
TEST(LessonControls, EachKeyActsOncePerPress) {
    const LessonDef l = lesson("sogetsu_basic_upright");
    auto scene = scene_for_lesson(l);
    ASSERT_TRUE(scene.ok());
    auto world = World::create(*scene);
    ASSERT_TRUE(world.ok());
    World& w = **world;
    sched::DeterministicClock clock(w.schedule);
    clock.run_for_us(100'000);
    const auto& frame = w.main.resource<const systems::ReceivedFrames>()->latest();
    LessonControls controls(l, footprint(l));
    platform::PointerState in;
    // A letter key (the lesson's), or Enter.
    const auto press_key = [&](const std::function<void(bool)>& set) {
        set(true);
        const auto down = controls.update(in, 1, frame, w.trainee);
        const auto held = controls.update(in, 1, frame, w.trainee);
        set(false);
        controls.update(in, 1, frame, w.trainee);
        return std::pair{down, held};
    };
    const auto press = [&](char letter) { return press_key([&](bool down) { in.set_letter(letter, down); }); };
    const auto [restart, restart_held] = press(reset_letter);
    EXPECT_TRUE(restart.restart);
    EXPECT_FALSE(restart_held.restart) << "held down, it does not ask again";
    EXPECT_FALSE(controls.ghosts());
    EXPECT_TRUE(press(ghost_letter).first.ghosts_toggled);
    EXPECT_TRUE(controls.ghosts());
    bool legend = false;
    for (const auto& line : controls.hud_lines()) legend = legend || line.find("targets (G): shin") != std::string::npos;
    EXPECT_TRUE(legend);
    press(ghost_letter);
    EXPECT_FALSE(controls.ghosts());
    const auto [enter, enter_held] = press_key([&](bool down) { in.finish_key = down; });
    ASSERT_TRUE(enter.score.has_value());
    ASSERT_TRUE(enter.score->ok());
    EXPECT_LT((*enter.score)->score, 20.0) << "nothing in the kenzan yet: only rules such as the kenzan off centre hold";
    EXPECT_FALSE(enter_held.score.has_value());
    EXPECT_TRUE(press(cut_letter).first.cut_for.empty()) << "nothing held, nothing cut";
    systems::TraineeCommand left_over;
    EXPECT_FALSE(w.trainee.pop(left_over));
    EXPECT_NE(controls.hud_lines().front().find("Sogetsu: Basic Upright Style"), std::string::npos) << controls.hud_lines().front();
}

namespace {
// The right hand holding a 340 mm cherry branch lying along x (a kenzan without pins).
components::FrameSnapshot holding_a_lying_cherry_branch() {
    components::FrameSnapshot frame{};
    frame.kenzan = components::Kenzan{};
    components::FlowerStatus f{};
    f.species = "cherry_branch";
    for (int i = 0; i <= 20; ++i) f.points_m.push_back({-0.2 + 0.017 * i, -0.15, 0.1});
    frame.flowers.push_back(f);
    frame.hands[1].present = true;
    frame.hands[1].holding = true;
    frame.hands[1].held_flower = 0;
    return frame;
}
} // namespace

// A first-time trainee takes a lying stem wherever the cursor is; held near its top it cannot be pushed
// in (turned, its long end swings into the table): the HUD says to take it near its bottom end.
TEST(LessonControls, AStemHeldFarFromItsBottomEndIsToBeTakenAgainNearThatEnd) {
    const LessonDef l = lesson("sogetsu_basic_upright");
    components::FrameSnapshot frame = holding_a_lying_cherry_branch();
    const auto& f = frame.flowers[0];
    const auto says = [&](glm::dvec3 hand) {
        frame.hands[1].position_m = hand;
        std::string all;
        for (const auto& line : advise_held_stem(l, footprint(l), frame, 1).lines) all += line + "\n";
        return all;
    };
    const std::string near_top = says(f.points_m[17]);
    EXPECT_NE(near_top.find("held 289 mm from its bottom end: to push it in, let go and take it near that end"), std::string::npos) << near_top;
    const std::string near_bottom = says(f.points_m[3]);
    EXPECT_EQ(near_bottom.find("from its bottom end"), std::string::npos) << near_bottom;
    EXPECT_NE(near_bottom.find("holding a cherry branch: 340 mm long"), std::string::npos) << near_bottom;
}

// A first-time trainee cut hikae with C "for 0.75 × soe", pushed it in leaning about 70 degrees and was
// scored 42 mm short, against the other ratio: the pins take more of a leaning stem than their height.
// Cut as C cuts it and stood at the model's tilt with its bottom a pin height deep, it measures its
// role's length above the kenzan.
TEST(LessonControls, AStemCutWithCForItsRoleMeasuresThatRolesLengthOnceItLeansInThePins) {
    const LessonDef l = lesson("sogetsu_basic_upright");
    components::FrameSnapshot frame = holding_a_lying_cherry_branch();
    frame.kenzan->pin.trunk_length_m = 0.011;
    frame.kenzan->pin.tip_length_m = 0.002;
    frame.flowers[0].species = "chrysanthemum";
    frame.hands[1].position_m = frame.flowers[0].points_m[3];
    const auto advice = advise_held_stem(l, footprint(l), frame, 1);
    ASSERT_EQ(advice.role, "hikae");
    const double target_m = nominal_length_m(l, 2);
    const auto model = model_arrangement(l, footprint(l));
    const auto hikae = std::find_if(model.stems.begin(), model.stems.end(), [](const ArrangementStem& s) { return s.role == "hikae"; });
    ASSERT_NE(hikae, model.stems.end());
    // The stem as it stands: straight, its bottom on the plate, a pin height under the pins' tops.
    const double pins = frame.kenzan->pin_height_m();
    const glm::dvec3 along = lesson_direction(hikae->tilt_rad, hikae->azimuth_rad);
    const glm::dvec3 bottom = frame.kenzan->origin_m;
    components::FrameSnapshot stood = frame;
    stood.hands[1] = {};
    stood.hands[1].held_flower = -1;
    auto& f = stood.flowers[0];
    f.in_kenzan = true;
    f.points_m.clear();
    for (int i = 0; i <= 20; ++i) f.points_m.push_back(bottom + along * (advice.keep_length_m * i / 20.0));
    const auto measured = measure_arrangement(stood);
    ASSERT_EQ(measured.stems.size(), 1u);
    EXPECT_NEAR(measured.stems[0].length_m, target_m, 0.002) << "cut to " << advice.keep_length_m << " m with " << pins << " m of pins, leaning "
                                                              << hikae->tilt_rad * 180 / 3.14159265358979323846 << " deg";
    EXPECT_GT(advice.keep_length_m - target_m, 2.0 * pins) << "at hikae's 75 degrees the pins take more than twice their height of it";
}

namespace {
// A second cherry branch standing in the kenzan where the model puts soe (so a held one is heading for
// a supporting stem).
void stand_cherry_as_soe(components::FrameSnapshot& frame, const LessonDef& l) {
    const auto model = model_arrangement(l, footprint(l));
    const auto soe = std::find_if(model.stems.begin(), model.stems.end(), [](const ArrangementStem& s) { return s.role == "soe"; });
    ASSERT_NE(soe, model.stems.end());
    components::FlowerStatus standing{};
    standing.species = "cherry_branch";
    standing.in_kenzan = true;
    const glm::dvec3 base = frame.kenzan->origin_m + glm::dvec3(soe->base_m, 0.0);
    for (int i = 0; i <= 10; ++i) standing.points_m.push_back(base + lesson_direction(soe->tilt_rad, soe->azimuth_rad) * (soe->length_m * i / 10.0));
    frame.flowers.push_back(standing);
}
} // namespace

namespace {
// A stem standing in the kenzan where the model puts a role, as the model stands it.
void stand_as_model(components::FrameSnapshot& frame, const LessonDef& l, const std::string& role, const std::string& species) {
    const auto model = model_arrangement(l, footprint(l));
    const auto m = std::find_if(model.stems.begin(), model.stems.end(), [&](const ArrangementStem& s) { return s.role == role; });
    ASSERT_NE(m, model.stems.end());
    components::FlowerStatus standing{};
    standing.species = species;
    standing.in_kenzan = true;
    const glm::dvec3 base = frame.kenzan->origin_m + glm::dvec3(m->base_m, 0.0);
    for (int i = 0; i <= 10; ++i) standing.points_m.push_back(base + lesson_direction(m->tilt_rad, m->azimuth_rad) * (m->length_m * i / 10.0));
    frame.flowers.push_back(standing);
}
} // namespace

// A first-time trainee was told "tilt it 75°" for hikae where the container's rim would not let it lean
// past about 70. The next step names the lean the rim allows (the model's), and why.
TEST(LessonControls, ALowStemIsToldTheLeanTheRimAllowsNotTheFormsSteeperOne) {
    const LessonDef l = lesson("sogetsu_basic_upright");
    const auto model = model_arrangement(l, footprint(l));
    const auto hikae = std::find_if(model.stems.begin(), model.stems.end(), [](const ArrangementStem& s) { return s.role == "hikae"; });
    ASSERT_NE(hikae, model.stems.end());
    const auto form = std::find_if(l.stems.begin(), l.stems.end(), [](const auto& m) { return m.role == "hikae"; });
    ASSERT_NE(form, l.stems.end());
    components::FrameSnapshot frame = holding_a_lying_cherry_branch();
    // The lesson's kenzan and container where its scene puts them.
    const auto scene = scene_for_lesson(l);
    ASSERT_TRUE(scene);
    auto kenzan = load_kenzan(scene->kenzan_layout);
    ASSERT_TRUE(kenzan);
    kenzan->origin_m = scene->kenzan_position_m;
    frame.kenzan = *kenzan;
    frame.container = container_of(*scene);
    frame.flowers[0].species = "chrysanthemum";
    frame.flowers[0].diameter_m = 0.006;
    frame.hands[1].position_m = frame.flowers[0].points_m[3];
    stand_as_model(frame, l, "shin", "willow_branch");
    stand_as_model(frame, l, "soe", "cherry_branch");
    const auto before_cut = advise_held_stem(l, footprint(l), frame, 1);
    ASSERT_EQ(before_cut.role, "hikae");
    // Cut to what C keeps.
    auto& held = frame.flowers[0].points_m;
    const glm::dvec3 from = held.front();
    for (std::size_t i = 0; i < held.size(); ++i) held[i] = from + (held[i] - from) * (before_cut.keep_length_m * 0.99 / 0.34);
    const auto cut = advise_held_stem(l, footprint(l), frame, 1);
    // The steepest lean that clears the rim from where hikae goes, a degree inside it.
    const glm::dvec3 want = lesson_direction(form->tilt_rad.target, hikae->azimuth_rad);
    const glm::dvec3 bottom = frame.kenzan->origin_m + glm::dvec3(bottom_for(hikae->base_m, want, frame.kenzan->pin_height_m()), 0.0);
    const auto clears = rim_tilt_rad(*frame.container, bottom, hikae->azimuth_rad, 0.3, 0.003);
    ASSERT_TRUE(clears.has_value());
    ASSERT_LT(*clears, form->tilt_rad.target - 2.0 * deg) << "the rim holds hikae up in this lesson";
    char expected[160];
    std::snprintf(expected, sizeof expected, "tilt it %.0f° toward the right front, as far as the rim lets it of the form's %.0f° (Ctrl+drag)",
                  (*clears - rim_margin_rad) / deg, form->tilt_rad.target / deg);
    EXPECT_EQ(cut.next_step.rfind(expected, 0), 0u) << cut.next_step;
    EXPECT_LT(cut.keep_length_m, before_cut.keep_length_m + 1e-9);
    // Upright shin is told the form's lean, with nothing of a rim.
    components::FrameSnapshot first = holding_a_lying_cherry_branch();
    first.flowers[0].species = "willow_branch";
    first.hands[1].position_m = first.flowers[0].points_m[3];
    const auto shin = advise_held_stem(l, footprint(l), first, 1);
    ASSERT_EQ(shin.role, "shin");
    EXPECT_EQ(shin.lines.front().find("rim"), std::string::npos) << shin.lines.front();
}

// A first-time trainee holding a fourth chrysanthemum read jushi instructions in the panel and "no role
// is left for this stem: let go of it away from the kenzan" as the next step, and never placed a jushi
// the score asked for. With soe standing, a second cherry branch is heading for a supporting stem: the
// next step says what to do with it, and the gauge shows the model jushi's lean.
TEST(LessonControls, AStemHeadingForASupportingRoleIsToldItsNextStepAndShownItsLean) {
    const LessonDef l = lesson("sogetsu_basic_upright");
    components::FrameSnapshot frame = holding_a_lying_cherry_branch();
    frame.hands[1].position_m = frame.flowers[0].points_m[3];
    stand_cherry_as_soe(frame, l);
    const auto advice = advise_held_stem(l, footprint(l), frame, 1);
    ASSERT_EQ(advice.role, "supporting");
    EXPECT_EQ(advice.next_step.rfind("press C to cut it as a supporting stem (jushi, to ", 0), 0u) << advice.next_step;
    ASSERT_TRUE(advice.gauge.has_value());
    EXPECT_EQ(advice.gauge->role, l.stems.size()) << "drawn in the colour after the main roles'";
    EXPECT_GT(advice.gauge->tilt_tolerance_rad, 0.0);
    // Cut, it is told where to lean it and where on the kenzan it goes, in words.
    auto& held = frame.flowers[0].points_m;
    const glm::dvec3 from = held.front();
    for (std::size_t i = 0; i < held.size(); ++i) held[i] = from + (held[i] - from) * (advice.keep_length_m * 0.99 / 0.34);
    const auto cut = advise_held_stem(l, footprint(l), frame, 1);
    EXPECT_EQ(cut.next_step.rfind("tilt it ", 0), 0u) << cut.next_step;
    EXPECT_NE(cut.next_step.find(" of the kenzan"), std::string::npos) << cut.next_step;
    EXPECT_EQ(cut.next_step.find("mm"), std::string::npos) << "no coordinates: " << cut.next_step;
    // Before it is taken, a press on it is named for that role (it read "no role of the form is left").
    frame.hands[1].holding = false;
    frame.hands[1].held_flower = -1;
    frame.hands[1].position_m = frame.flowers[0].points_m[3];
    LessonControls controls(l, footprint(l));
    systems::TraineeChannel channel;
    (void)controls.update(platform::PointerState{}, 1, frame, channel);
    EXPECT_NE(controls.next_step().find("hold the left button to take the cherry branch for a supporting stem (jushi)"), std::string::npos) << controls.next_step();
    // Uncut, a press takes it above what C will cut off for it (by its end, it held the piece that came
    // off); cut already, near its end.
    EXPECT_DOUBLE_EQ(grip_along_m(l, footprint(l), frame, 1), 0.06);
    components::FrameSnapshot uncut = holding_a_lying_cherry_branch();
    stand_cherry_as_soe(uncut, l);
    uncut.hands[1].holding = false;
    uncut.hands[1].held_flower = -1;
    uncut.hands[1].position_m = uncut.flowers[0].points_m[15];
    const double along = grip_along_m(l, footprint(l), uncut, 1);
    EXPECT_NEAR(along, 0.34 - advice.keep_length_m + 0.03, 0.002);
    const auto grip = bottom_grip_for(uncut, 1, along);
    ASSERT_TRUE(grip.has_value());
    EXPECT_NEAR(grip->x - uncut.flowers[0].points_m.front().x, along, 0.017) << "the stem point nearest that far up";
    (void)controls.update(platform::PointerState{}, 1, uncut, channel);
    EXPECT_NE(controls.next_step().find(" mm up from its bottom end, above what C cuts off"), std::string::npos) << controls.next_step();
    // Pressed near its bottom end, on the part C will cut off, likewise (a trainee took a
    // chrysanthemum 100 mm up, and C refused to cut it for a 59 mm jushi).
    uncut.hands[1].position_m = uncut.flowers[0].points_m[4];
    const auto low = bottom_grip_for(uncut, 1, grip_along_m(l, footprint(l), uncut, 1));
    ASSERT_TRUE(low.has_value());
    EXPECT_NEAR(low->x - uncut.flowers[0].points_m.front().x, along, 0.017);
    // Taken there, it is to be cut, not taken again by its end (far from its end now, near it once cut).
    uncut.hands[1].holding = true;
    uncut.hands[1].held_flower = 0;
    uncut.hands[1].position_m = *low;
    const auto taken = advise_held_stem(l, footprint(l), uncut, 1);
    EXPECT_EQ(taken.next_step.rfind("press C to cut it as a supporting stem", 0), 0u) << taken.next_step;
    for (const auto& line : taken.lines) EXPECT_EQ(line.find("take it near that end"), std::string::npos) << line;
}

// Taken by its bottom end and cut with C for a short jushi, the hand held the piece that came off and
// the flower hung 120 mm from the cube: C cuts nothing then and says to take it nearer the flower; held
// above the cut, C cuts.
TEST(LessonControls, CCutsNothingWhenTheHandHoldsThePartItWouldCutOff) {
    const LessonDef l = lesson("sogetsu_basic_upright");
    components::FrameSnapshot frame = holding_a_lying_cherry_branch();
    stand_cherry_as_soe(frame, l);
    frame.hands[1].position_m = frame.flowers[0].points_m[3]; // 51 mm from its bottom end
    LessonControls controls(l, footprint(l));
    systems::TraineeChannel channel;
    platform::PointerState in;
    in.set_letter('C', true);
    const auto near_bottom = controls.update(in, 1, frame, channel);
    EXPECT_TRUE(near_bottom.cut_for.empty());
    systems::TraineeCommand command;
    EXPECT_FALSE(channel.pop(command)) << "nothing cut";
    EXPECT_EQ(controls.next_step().rfind("C would cut off the part in your hand: let go, and take it again above its lowest ", 0), 0u) << controls.next_step();
    in.set_letter('C', false);
    (void)controls.update(in, 1, frame, channel);
    frame.hands[1].position_m = frame.flowers[0].points_m[19]; // near its top, above the cut
    in.set_letter('C', true);
    const auto near_top = controls.update(in, 1, frame, channel);
    EXPECT_EQ(near_top.cut_for, "supporting");
    EXPECT_TRUE(channel.pop(command)) << "cut";
}

// In a shoka the stems rise from the water as one line: the HUD tells a trainee holding soe's cherry
// branch to bend it first, where and about how far, and how with a mouse; Sogetsu's forms want no bend.
TEST(LessonControls, AShokaRoleThatLeansAwayFromTheLineIsToBeBentWithBothHandsFirst) {
    components::FrameSnapshot frame = holding_a_lying_cherry_branch();
    frame.hands[1].position_m = frame.flowers[0].points_m[3];
    const auto says = [&](const char* id) {
        const LessonDef l = lesson(id);
        std::string all;
        for (const auto& line : advise_held_stem(l, footprint(l), frame, 1).lines) all += line + "\n";
        return all;
    };
    const std::string shoka = says("ikenobo_shoka_shofutai");
    EXPECT_NE(shoka.find("for soe: C cuts it to"), std::string::npos) << shoka;
    // Soe's length follows shin's: said so, as the form has it while no shin stands.
    EXPECT_NE(shoka.find(" × shin as the form has it; "), std::string::npos) << shoka;
    EXPECT_NE(shoka.find("the form's stems rise as one line 60-80 mm above the water: first bend it about 40° 70 mm from its cut end"), std::string::npos) << shoka; // this kenzan{} has no pins
    EXPECT_NE(shoka.find("to bend: Tab, take it with the other hand beside this one"), std::string::npos) << shoka;
    const std::string upright = says("sogetsu_basic_upright");
    EXPECT_EQ(upright.find("bend"), std::string::npos) << upright;
}

// Holding a leafy stem for a role, the HUD counts the leaves that would stand in the water once it is
// cut for it and pushed in, and says how to strip them; the cut's part and the leaves high up are not
// counted, nor is anything in a lesson without the rule.
TEST(LessonControls, LeavesThatWouldStandInTheWaterAreCountedForTheHeldStem) {
    components::FrameSnapshot frame = holding_a_lying_cherry_branch();
    frame.hands[1].position_m = frame.flowers[0].points_m[3];
    auto& f = frame.flowers[0];
    f.species = "chrysanthemum";
    for (const std::uint32_t point : {1u, 2u, 3u, 19u}) f.parts.push_back({components::PartKind::leaf, point, {0.0, 0.01, 0.0}, "meshes/leaf.gltf"});
    f.parts.push_back({components::PartKind::petal, 2u, {0.0, 0.01, 0.0}, "meshes/petal.gltf"});
    const auto says = [&](LessonDef l) {
        std::string all;
        for (const auto& line : advise_held_stem(l, footprint(l), frame, 1).lines) all += line + "\n";
        return all;
    };
    LessonDef l = lesson("sogetsu_basic_upright");
    const std::string hikae = says(l);
    // For hikae (245 mm, 75 degrees) the 340 mm stem loses 95 mm: its three low leaves go with the cut,
    // and the top one, 228 mm up the stem, stands 59 mm high, over the 32 mm of water.
    EXPECT_EQ(hikae.find("would stand in the water"), std::string::npos) << hikae;
    for (auto& p : f.points_m) p.x = -0.2 + (p.x + 0.2) * 0.25; // 85 mm long: nothing to cut
    // Leaning 75 degrees, even the top leaf (81 mm up the stem) stands 21 mm high: all four.
    const std::string short_one = says(l);
    EXPECT_NE(short_one.find("4 leaves would stand in the water (they rot): Tab, the other hand's cube on each, P strips it"), std::string::npos) << short_one;
    std::erase_if(l.rules, [](const RuleDef& r) { return r.kind == RuleKind::no_leaves_under_water; });
    EXPECT_EQ(says(l).find("would stand in the water"), std::string::npos) << "a lesson without the rule";
}

// Before P is pressed the HUD says what it would take at the hand's cube, chosen as the pruning
// system chooses: the nearest leaf or blossom, or twig (cut at its fork), within the cube's half edge.
TEST(LessonControls, TheHudSaysWhatPWouldPruneAtTheCube) {
    components::FrameSnapshot frame = holding_a_lying_cherry_branch();
    frame.hands[1].holding = false;
    frame.hands[1].held_flower = -1;
    frame.hands[1].edge_m = 0.02;
    auto& f = frame.flowers[0];
    f.parts.push_back({components::PartKind::leaf, 10u, {0.0, 0.003, 0.0}, "meshes/leaf.gltf"});
    components::TwigStatus twig;
    twig.points_m = {f.points_m[15], f.points_m[15] + glm::dvec3{0.0, 0.05, 0.0}, f.points_m[15] + glm::dvec3{0.0, 0.1, 0.0}};
    twig.diameter_m = 0.002;
    f.twigs.push_back(twig);
    frame.hands[1].position_m = f.points_m[10];
    EXPECT_EQ(prune_preview(frame, 1), "P here: strips a leaf of the cherry branch");
    frame.hands[1].position_m = f.points_m[15] + glm::dvec3{0.0, 0.06, 0.0};
    EXPECT_EQ(prune_preview(frame, 1), "P here: cuts off a twig of the cherry branch at its fork");
    frame.hands[1].position_m = f.points_m[3] + glm::dvec3{0.0, 0.0, 0.05};
    EXPECT_EQ(prune_preview(frame, 1), "") << "nothing within the cube's reach";
    frame.hands[1].position_m = f.points_m[10];
    frame.hands[1].holding = true;
    EXPECT_EQ(prune_preview(frame, 1), "P here: strips a leaf of the cherry branch") << "a hand that holds a stem prunes at its fist as well";
}

// The Ikenobo teacher prunes soe's side twigs before bending it: the prunings are on record with the
// cuts ("prune" lines), and the session replays to the same score and state with them (and to another
// without them).
TEST(LessonSession, PruningIsRecordedAndReplayed) {
    const LessonDef l = lesson("ikenobo_shoka_shofutai");
    const auto dir = std::filesystem::temp_directory_path() / "ikebana-session-prune-test";
    std::filesystem::remove_all(dir);
    DemoOptions options;
    options.record_dir = dir.string();
    const auto demo = run_lesson_demo(l, options);
    ASSERT_TRUE(demo.ok()) << demo.error().message;
    const auto commands = assets::read_text_file(dir / "commands.csv");
    ASSERT_TRUE(commands.ok());
    EXPECT_NE(commands->find(",prune,1,0\n"), std::string::npos) << *commands;
    const auto replayed = replay_lesson_session(dir);
    ASSERT_TRUE(replayed.ok()) << replayed.error().message;
    EXPECT_EQ(replayed->score.score, demo->score.score);
    EXPECT_EQ(replayed->state_hash, demo->state_hash);
    EXPECT_TRUE(replayed->parted.empty());
    std::string cuts_only;
    for (std::size_t from = 0; from < commands->size();) {
        const std::size_t to = commands->find('\n', from);
        const std::string line = commands->substr(from, to - from + 1);
        if (line.find(",prune,") == std::string::npos) cuts_only += line;
        from = to + 1;
    }
    ASSERT_TRUE(assets::write_text_file(dir / "commands.csv", cuts_only).ok());
    const auto unpruned = replay_lesson_session(dir);
    ASSERT_TRUE(unpruned.ok()) << unpruned.error().message;
    EXPECT_NE(unpruned->state_hash, demo->state_hash);
    EXPECT_FALSE(unpruned->parted.empty());
    // A prune line with a value is refused with the file and line named.
    const auto bad = parse_session_commands("1000,prune,1,0.5\n", "commands.csv");
    ASSERT_FALSE(bad);
    EXPECT_EQ(bad.error().message.rfind("commands.csv: line 1: expected time_us,cut,hand,keep_length_m (hand 0 or 1, a length in metres), time_us,prune,hand,0, ", 0), 0u) << bad.error().message;
    std::filesystem::remove_all(dir);
}

// A demonstration on record (device samples, the cuts as the simulation took them) replays on the
// deterministic clock to the same score and the same final state, component by component.
TEST(LessonSession, ADemonstrationOnRecordReplaysToTheSameScoreAndStateHash) {
    const LessonDef l = lesson("sogetsu_basic_upright");
    const auto dir = std::filesystem::temp_directory_path() / "ikebana-session-test";
    std::filesystem::remove_all(dir);
    DemoOptions options;
    options.record_dir = dir.string();
    const auto demo = run_lesson_demo(l, options);
    ASSERT_TRUE(demo.ok()) << demo.error().message;
    const auto replayed = replay_lesson_session(dir);
    ASSERT_TRUE(replayed.ok()) << replayed.error().message;
    EXPECT_EQ(replayed->score.score, demo->score.score);
    EXPECT_EQ(replayed->recorded_state_hash, demo->state_hash);
    EXPECT_EQ(replayed->state_hash, demo->state_hash);
    EXPECT_TRUE(replayed->parted.empty());
    EXPECT_EQ(replayed->kind, "demonstration");
    // Five cuts, one per role and one per supporting stem (the jushi that hide the kenzan), and the two
    // prunings that strip hikae's low leaves (at 68 degrees its lowest pair would be in the water), on record.
    const auto commands = assets::read_text_file(dir / "commands.csv");
    ASSERT_TRUE(commands.ok());
    EXPECT_EQ(std::count(commands->begin(), commands->end(), '\n'), 7);
    EXPECT_NE(demo->steps.end(), std::find_if(demo->steps.begin(), demo->steps.end(), [](const auto& s) { return s.what == "hikae: strip the 2 leaves that would stand in the water"; }));
    // The review's timeline: the three cuts at the ticks they were taken, and each role's stem going
    // into the kenzan after its cut.
    const auto parsed = parse_session_commands(*commands, "commands.csv");
    ASSERT_TRUE(parsed.ok());
    const auto marks = session_timeline(dir);
    ASSERT_TRUE(marks.ok()) << marks.error().message;
    std::vector<std::int64_t> cuts, insertions;
    std::vector<std::int64_t> cut_commands;
    for (const auto& c : *parsed) {
        if (c.command.kind == systems::TraineeCommand::Kind::cut) cut_commands.push_back(c.at_us);
    }
    for (const auto& m : *marks) {
        if (m.kind == TimelineMark::Kind::cut && m.what.rfind("cut:", 0) == 0) cuts.push_back(m.at_us);
        if (m.kind == TimelineMark::Kind::insertion) insertions.push_back(m.at_us);
    }
    ASSERT_EQ(cuts.size(), 5u);
    ASSERT_EQ(cut_commands.size(), 5u);
    for (std::size_t i = 0; i < 5; ++i) EXPECT_EQ(cuts[i], cut_commands[i]);
    ASSERT_GE(insertions.size(), 5u);
    for (std::size_t i = 0; i < 5; ++i) EXPECT_GT(insertions[i], cuts[i]) << "a stem goes in after it is cut to length";
    EXPECT_TRUE(std::is_sorted(marks->begin(), marks->end(), [](const TimelineMark& a, const TimelineMark& b) { return a.at_us < b.at_us; }));
    // Without its cuts the replay is another session: it says where it parts.
    ASSERT_TRUE(assets::write_text_file(dir / "commands.csv", "").ok());
    const auto uncut = replay_lesson_session(dir);
    ASSERT_TRUE(uncut.ok()) << uncut.error().message;
    EXPECT_NE(uncut->state_hash, demo->state_hash);
    EXPECT_FALSE(uncut->parted.empty());
    std::filesystem::remove_all(dir);
}

namespace {
// A window session's recording made on the deterministic clock: `until_enter` runs it up to the
// trainee's Enter (turning the camera, skipping as the clock's clamp would), the score is taken from
// the newest frame then, as the window takes it, and the session ends at `end_us`. The score, or none.
std::optional<double> record_window_session(World& w, const LessonDef& l, const std::filesystem::path& dir, std::int64_t end_us,
                                            const std::function<void(sched::DeterministicClock&, SessionRecorder&)>& until_enter) {
    auto recorder = SessionRecorder::create(dir, /*real_time=*/false);
    if (!recorder.ok()) {
        ADD_FAILURE() << recorder.error().message;
        return std::nullopt;
    }
    (*recorder)->attach(w);
    sched::DeterministicClock clock(w.schedule);
    until_enter(clock, **recorder);
    const auto& scored = w.main.resource<const systems::ReceivedFrames>()->latest();
    const auto score = score_form(l, measure_arrangement(scored), footprint(l));
    if (!score.ok()) {
        ADD_FAILURE() << score.error().message;
        return std::nullopt;
    }
    SessionRecorder::WindowRun run;
    run.scored_frame_us = scored.sim_time_us;
    clock.run_until(end_us);
    (*recorder)->detach(w);
    if (auto done = (*recorder)->finish_window(l, "practice", run, end_us, score->score, w); !done.ok()) {
        ADD_FAILURE() << done.error().message;
        return std::nullopt;
    }
    return score->score;
}
} // namespace

// A window session's recording: the camera's turn and the clock's skip are on record at their ticks,
// the score is the published frame's, and the replay reaches the simulation's state. Without the turn
// (the hand then moves the other way) or the skip (1 kHz firings run that the session dropped) it parts.
TEST(LessonSession, AWindowSessionsTurnsAndSkipsReplayAtTheirTicks) {
    const LessonDef l = lesson("sogetsu_basic_upright");
    const auto dir = std::filesystem::temp_directory_path() / "ikebana-window-session-test";
    std::filesystem::remove_all(dir);
    auto scene = scene_for_lesson(l);
    ASSERT_TRUE(scene.ok());
    auto made = World::create(*scene);
    ASSERT_TRUE(made.ok()) << made.error().message;
    World& w = **made;
    std::vector<devices::Keyframe> path{{0.0, {0.0, 0.0, 0.0}, {0, 0, 0}, 0}, {3.0, {0.08, 0.05, 0.02}, {0, 0, 0}, 0}};
    w.attach_device(1, std::make_unique<devices::ScriptedDevice>(path, devices::ScriptedDevice::Mode::interpolate, "moving hand"));
    const auto score = record_window_session(w, l, dir, 2'500'000, [&](sched::DeterministicClock& clock, SessionRecorder& recorder) {
        clock.run_until(1'000'000);
        w.view.yaw_rad.store(0.6); // the trainee turns the camera
        clock.run_until(1'500'000);
        EXPECT_TRUE(recorder.commands().write("1500000,skip,0,1700000\n")); // as the window's on_skip writes it
        clock.skip_lane(0, 1'700'000);
        clock.run_until(2'000'000);
    });
    ASSERT_TRUE(score.has_value());

    const auto replayed = replay_lesson_session(dir);
    ASSERT_TRUE(replayed.ok()) << replayed.error().message;
    EXPECT_EQ(replayed->state_hash, w.sim.state_hash());
    EXPECT_EQ(replayed->score.score, *score);
    EXPECT_TRUE(replayed->parted.empty());
    const auto commands = assets::read_text_file(dir / "commands.csv");
    ASSERT_TRUE(commands.ok());
    EXPECT_NE(commands->find(",view,0,0.59999999999999998\n"), std::string::npos) << *commands;
    const auto without = [&](const std::string& what) {
        std::string kept;
        std::size_t from = 0;
        while (from < commands->size()) {
            const auto to = commands->find('\n', from);
            const auto line = commands->substr(from, to - from + 1);
            if (line.find(what) == std::string::npos) kept += line;
            from = to + 1;
        }
        EXPECT_TRUE(assets::write_text_file(dir / "commands.csv", kept).ok());
        const auto r = replay_lesson_session(dir);
        EXPECT_TRUE(assets::write_text_file(dir / "commands.csv", *commands).ok());
        EXPECT_TRUE(r.ok()) << r.error().message; // it replays, elsewhere
        return r.ok() ? r->state_hash : w.sim.state_hash();
    };
    EXPECT_NE(without(",view,"), w.sim.state_hash());
    EXPECT_NE(without(",skip,"), w.sim.state_hash());
    std::filesystem::remove_all(dir);
}

// A device that went away in a window session (unplugged, a read failed) is away in the replay for
// the same ticks: the hand's `connected` and its count of disconnects come out the same.
TEST(LessonSession, ADeviceThatWentAwayIsAwayInTheReplayForTheSameTicks) {
    const LessonDef l = lesson("sogetsu_basic_upright");
    const auto dir = std::filesystem::temp_directory_path() / "ikebana-away-session-test";
    std::filesystem::remove_all(dir);
    auto scene = scene_for_lesson(l);
    ASSERT_TRUE(scene.ok());
    auto made = World::create(*scene);
    ASSERT_TRUE(made.ok()) << made.error().message;
    World& w = **made;
    // A hand whose reads fail from 0.4 s to 0.9 s (as an unplugged device's do), moving all along.
    struct Flaky final : devices::HapticDevice {
        devices::ScriptedDevice inner{{{0.0, {0.0, 0.0, 0.0}, {0, 0, 0}, 0}, {2.0, {0.05, 0.03, 0.02}, {0, 0, 0}, 0}}, devices::ScriptedDevice::Mode::interpolate, "flaky"};
        const devices::DeviceCapabilities& capabilities() const override { return inner.capabilities(); }
        Result<devices::DeviceSample> poll(std::int64_t now_us) override {
            if (now_us >= 400'000 && now_us < 900'000) return make_error(ErrorCode::device_error, "unplugged");
            return inner.poll(now_us);
        }
        Result<void> send_force(glm::dvec3 f) override { return inner.send_force(f); }
    };
    w.attach_device(1, std::make_unique<Flaky>());
    const auto score = record_window_session(w, l, dir, 2'000'000, [](sched::DeterministicClock& clock, SessionRecorder&) { clock.run_until(1'500'000); });
    ASSERT_TRUE(score.has_value());
    const auto commands = assets::read_text_file(dir / "commands.csv");
    ASSERT_TRUE(commands.ok());
    EXPECT_NE(commands->find("400000,gone,1,0\n"), std::string::npos) << *commands;
    EXPECT_NE(commands->find("900000,back,1,0\n"), std::string::npos) << *commands;
    const auto replayed = replay_lesson_session(dir);
    ASSERT_TRUE(replayed.ok()) << replayed.error().message;
    EXPECT_EQ(replayed->state_hash, w.sim.state_hash());
    EXPECT_TRUE(replayed->parted.empty());
    // Without the two lines the replay's hand never went away: it parts.
    std::string kept = *commands;
    for (const char* line : {"400000,gone,1,0\n", "900000,back,1,0\n"}) kept.erase(kept.find(line), std::string(line).size());
    ASSERT_TRUE(assets::write_text_file(dir / "commands.csv", kept).ok());
    const auto unaware = replay_lesson_session(dir);
    ASSERT_TRUE(unaware.ok()) << unaware.error().message;
    EXPECT_NE(unaware->state_hash, w.sim.state_hash());
    std::filesystem::remove_all(dir);
}

TEST(LessonSession, ACommandLineOutOfOrderOrNotACutIsRefusedWithItsFileAndLine) {
    const auto ok = parse_session_commands("100,cut,1,0.3\n200,cut,0,0.25\n", "c.csv");
    ASSERT_TRUE(ok.ok()) << ok.error().message;
    ASSERT_EQ(ok->size(), 2u);
    EXPECT_EQ((*ok)[1].at_us, 200);
    EXPECT_EQ((*ok)[1].command.hand, 0);
    const auto backwards = parse_session_commands("100,cut,1,0.3\n50,cut,1,0.2\n", "c.csv");
    ASSERT_FALSE(backwards.ok());
    EXPECT_EQ(backwards.error().message.rfind("c.csv: line 2: expected time_us,cut,hand,keep_length_m", 0), 0u) << backwards.error().message;
    const auto bend = parse_session_commands("100,bend,1,0.3\n", "c.csv");
    ASSERT_FALSE(bend.ok());
    EXPECT_NE(bend.error().message.find("c.csv: line 1:"), std::string::npos);
    EXPECT_FALSE(parse_session_commands("100,cut,2,0.3\n", "c.csv").ok());    // a third hand
    EXPECT_FALSE(parse_session_commands("100,cut,1,-0.3\n", "c.csv").ok());   // no length
    EXPECT_FALSE(parse_session_commands("100,cut,1,0.3 x\n", "c.csv").ok());  // trailing words
    // The window's lines: the camera's yaw, and the clock's skips (forward, to a whole microsecond).
    const auto window = parse_session_commands("100,view,0,-0.25\n150,skip,0,50150\n", "c.csv");
    ASSERT_TRUE(window.ok()) << window.error().message;
    EXPECT_EQ((*window)[0].what, SessionCommand::What::view);
    EXPECT_EQ((*window)[0].value, -0.25);
    EXPECT_EQ((*window)[1].what, SessionCommand::What::skip);
    EXPECT_EQ((*window)[1].value, 50150.0);
    EXPECT_FALSE(parse_session_commands("100,skip,0,50\n", "c.csv").ok());      // backwards
    EXPECT_FALSE(parse_session_commands("100,skip,0,150.5\n", "c.csv").ok());   // not a microsecond
    EXPECT_FALSE(parse_session_commands("100,view,1,0.2\n", "c.csv").ok());     // a view has no hand
    EXPECT_FALSE(parse_session_commands("100,view,0,nan\n", "c.csv").ok());
    const auto away = parse_session_commands("100,gone,1,0\n200,back,1,0\n", "c.csv");
    ASSERT_TRUE(away.ok()) << away.error().message;
    EXPECT_EQ((*away)[0].what, SessionCommand::What::gone);
    EXPECT_EQ((*away)[1].command.hand, 1);
    EXPECT_FALSE(parse_session_commands("100,gone,2,0\n", "c.csv").ok());
    EXPECT_FALSE(parse_session_commands("100,back,0,1\n", "c.csv").ok());
}

// A session.json is a file anyone may hand over: the lesson it names is a shipped one's id or a file
// beside it (the recorder copies a designer's lesson into the recording), never any file on the
// machine, and the answer is the same whether or not the file is there.
TEST(LessonSession, ASessionNamesItsLessonOnlyBesideItOrShipped) {
    const auto dir = std::filesystem::temp_directory_path() / "ikebana-session-lesson-path";
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    for (const std::string named : {"/etc/shadow", "/etc/no-such-lesson.json", "../../etc/passwd"}) {
        ASSERT_TRUE(assets::write_text_file(dir / "session.json", R"({"format": "ikebana-session/1", "lesson": ")" + named +
                                                          R"(", "kind": "practice", "scored_at_us": 0, "end_us": 10, "score": 50, "state_hash": "00000000000000ff"})"));
        const auto replayed = replay_lesson_session(dir);
        ASSERT_FALSE(replayed.ok());
        EXPECT_NE(replayed.error().message.find("/lesson: \"" + named + "\" is outside session.json's folder and the assets folder"), std::string::npos)
            << replayed.error().message;
    }
    std::filesystem::remove_all(dir);
}

TEST(LessonSession, ASessionFileNamesTheFieldItLacks) {
    const auto missing = parse_session(R"({"format": "ikebana-session/1", "lesson": "x", "kind": "practice", "scored_at_us": 0, "end_us": 10, "score": 50})", "s.json");
    ASSERT_FALSE(missing.ok());
    EXPECT_NE(missing.error().message.find("s.json"), std::string::npos);
    EXPECT_NE(missing.error().message.find("state_hash"), std::string::npos) << missing.error().message;
    const auto order = parse_session(
        R"({"format": "ikebana-session/1", "lesson": "x", "kind": "practice", "scored_at_us": 20, "end_us": 10, "score": 50, "state_hash": "00000000000000ff"})", "s.json");
    ASSERT_FALSE(order.ok());
    EXPECT_NE(order.error().message.find("/scored_at_us"), std::string::npos) << order.error().message;
    // A day's end (it replayed for two hours) is no lesson: four hours is the most.
    const auto day = parse_session(
        R"({"format": "ikebana-session/1", "lesson": "x", "kind": "practice", "scored_at_us": 20, "end_us": 86400000000, "score": 50, "state_hash": "00000000000000ff"})", "s.json");
    ASSERT_FALSE(day.ok());
    EXPECT_NE(day.error().message.find("/end_us"), std::string::npos) << day.error().message;
    EXPECT_TRUE(parse_session(
        R"({"format": "ikebana-session/1", "lesson": "x", "kind": "practice", "scored_at_us": 20, "end_us": 14400000000, "score": 50, "state_hash": "00000000000000ff"})", "s.json"));
}

// The layout a test checks the window by: panels, views and scene boxes read back as written, and a
// panel over a stem (or over an eye's view) is found and named; touching edges are not covering.
TEST(WindowState, ThePanelsLayoutIsReadBackAndAPanelOverTheSceneIsNamed) {
    WindowState s;
    s.layout.panels = {{"session", 0, {896, 0}, {384, 720}}};
    s.layout.views = {{"view", 0, {0, 0}, {896, 720}}};
    s.layout.scene = {{"kenzan", 0, {400, 450}, {80, 40}}, {"stem 2: willow_branch", 0, {500, 40}, {396, 500}}};
    const auto back = parse_window_state(window_state_json(s), "state.json");
    ASSERT_TRUE(back.ok()) << back.error().message;
    ASSERT_EQ(back->layout.scene.size(), 2u);
    EXPECT_EQ(back->layout.scene[1].name, "stem 2: willow_branch");
    EXPECT_EQ(back->layout.scene[1].size_px, glm::dvec2(396, 500));
    EXPECT_EQ(panel_over_scene(*back), std::nullopt) << "the stem's box ends where the panel starts";
    s.layout.scene[1].size_px.x = 436; // a tall willow leaning into the column
    EXPECT_EQ(panel_over_scene(s), "'session' covers 'stem 2: willow_branch' by 40x500 px");
    s.layout.scene[1].size_px.x = 396;
    s.layout.panels[0].min_px.x = 800; // a panel drawn over the view
    EXPECT_EQ(panel_over_scene(s), "'session' covers 'view' by 96x720 px");
    auto bad = nlohmann::json::parse(window_state_json(s));
    bad["layout"]["panels"][0]["rect_px"] = {1, 2, -3, 4};
    const auto refused = parse_window_state(bad.dump(), "state.json");
    ASSERT_FALSE(refused.ok());
    EXPECT_EQ(refused.error().message, "state.json: a box in 'layout.panels' has a negative size");
}

// What the window writes each frame for a script that works it is read back the same.
TEST(WindowState, WhatTheWindowWritesIsReadBackTheSame) {
    WindowState s;
    s.frame = 42;
    s.input_read_at_us = 123456789;
    s.sim_time_us = 5'000'000;
    s.window_px = {1200, 675};
    s.cursor_px = {600.5, 300};
    s.hands[1] = {true, 1, {0.1, -0.2, 0.3}, {0.1, -0.2, 0.25}, {0.0, 0.0, 24.0}, {0.0, 0.0, 3.0}, true, "answering"};
    WindowState::Flower f;
    f.species = "cherry_branch";
    f.points_m = {{0, 0, 0.01}, {0.01, 0, 0.2}};
    f.in_kenzan = true;
    f.fallen = true;
    f.fall_reason = components::FallReason::tipped;
    f.yield_holding_nm = 0.002;
    f.pins_engaged = 7;
    f.depth_m = 0.012;
    s.flowers = {f};
    s.kenzan_origin_m = glm::dvec3{0.03, 0.04, 0.005};
    s.kenzan_pin_height_m = 0.013;
    s.results = 1;
    s.result_json = R"({"score":96})";
    const auto back = parse_window_state(window_state_json(s), "state.json");
    ASSERT_TRUE(back.ok()) << back.error().message;
    EXPECT_EQ(back->frame, 42u);
    EXPECT_EQ(back->input_read_at_us, 123456789);
    EXPECT_EQ(back->cursor_px, s.cursor_px);
    EXPECT_EQ(back->hands[1].held_flower, 1);
    EXPECT_EQ(back->hands[1].device_m, s.hands[1].device_m);
    EXPECT_EQ(back->hands[1].force_sent_n, s.hands[1].force_sent_n) << "the force the device got, after the safety chain";
    EXPECT_EQ(back->hands[1].force_asked_n, s.hands[1].force_asked_n);
    EXPECT_TRUE(back->hands[1].pushes);
    ASSERT_EQ(back->flowers.size(), 1u);
    EXPECT_EQ(back->flowers[0].points_m, f.points_m);
    EXPECT_EQ(back->flowers[0].fall_reason, components::FallReason::tipped);
    EXPECT_EQ(back->flowers[0].pins_engaged, 7u);
    ASSERT_TRUE(back->kenzan_origin_m.has_value());
    EXPECT_EQ(*back->kenzan_origin_m, *s.kenzan_origin_m);
    EXPECT_EQ(nlohmann::json::parse(back->result_json)["score"], 96);
    const auto broken = parse_window_state(R"({"frame": 1, "input_read_at_us": 0, "sim_time_us": 0, "window_px": [1, 1], "cursor_px": [0, 0], "hands": []})", "state.json");
    ASSERT_FALSE(broken.ok());
    EXPECT_EQ(broken.error().message, "state.json: field 'hands' should hold two hands");
    // An integer out of its field's range (a fuzzer's 36-digit pin count, read as a float) or a
    // fraction is refused by name; converting it was undefined behaviour.
    auto state = nlohmann::json::parse(window_state_json(s));
    for (const char* bad : {"666666666666666666666666666666666668", "4.5", "-1", "4294967296"}) {
        auto text = state.dump();
        const std::string field = "\"pins_engaged\":";
        const auto at = text.find(field);
        ASSERT_NE(at, std::string::npos);
        const auto end = text.find_first_of(",}", at + field.size());
        text.replace(at + field.size(), end - at - field.size(), bad);
        const auto refused = parse_window_state(text, "state.json");
        ASSERT_FALSE(refused.ok()) << bad;
        EXPECT_EQ(refused.error().message, "state.json: field 'pins_engaged' should be an integer in range") << bad;
    }
}

// G shows the form's model behind the container as the flowers themselves (stems along the model's
// lines, heads, petals and leaves as their species have them), each tip marked in its role's colour.
TEST(ModelArrangement, TheModelIsDrawnAsItsFlowersBehindTheContainerWithEachTipMarkedInItsRolesColour) {
    const LessonDef l = lesson("sogetsu_basic_upright");
    const auto footprint = footprint_of(l);
    ASSERT_TRUE(footprint.ok());
    auto scene = scene_for_lesson(l);
    ASSERT_TRUE(scene.ok());
    auto world = World::create(*scene);
    ASSERT_TRUE(world.ok());
    const glm::dvec3 kenzan = (*world)->sim.single<components::Kenzan>()->origin_m;
    const glm::dvec3 plate = model_plate_origin(l, kenzan);
    const glm::dvec2 centre = glm::dvec2(kenzan) - l.kenzan_offset_m;
    EXPECT_GT(plate.y, centre.y + 0.5 * l.container.front_to_back_m + 0.1) << "behind the container, not in it";
    EXPECT_GT(plate.x, centre.x + 0.25 * l.container.width_m) << "and right of it";
    render::DrawList list;
    add_model_flowers(list, l, *footprint, plate, (*world)->species);
    const Arrangement model = model_arrangement(l, *footprint);
    std::size_t segments = 0, part_instances = 0, expected_parts = 0;
    std::map<std::string, std::size_t> per_mesh;
    for (const auto& b : list.batches) per_mesh[b.mesh] += b.instances.size();
    segments = per_mesh["cylinder"];
    EXPECT_EQ(segments, model.stems.size() * 20) << "twenty segments a stem";
    std::set<std::string> part_meshes;
    for (const auto& s : model.stems) {
        const auto& sp = (*world)->species.at(s.species);
        for (const auto& p : parts_of(sp, 21)) {
            if (p.mesh.empty()) continue;
            ++expected_parts;
            part_meshes.insert(p.mesh);
        }
        if (!sp.head_mesh.empty()) {
            EXPECT_GE(per_mesh[sp.head_mesh], 1u) << s.species << "'s head";
        }
    }
    for (const auto& m : part_meshes) part_instances += per_mesh[m];
    EXPECT_GE(part_instances, expected_parts) << "every petal and leaf the species have";
    EXPECT_GT(expected_parts, 0u);
    // One marker per role in its colour, above the tip of the model stem.
    for (std::size_t i = 0; i < l.stems.size(); ++i) {
        std::size_t markers = 0;
        for (const auto& b : list.batches) {
            if (b.mesh != "cube") continue;
            for (const auto& inst : b.instances) {
                const glm::vec3 c(inst.colour);
                if (glm::length(c - role_colour(i).rgb) < 1e-6f) ++markers;
            }
        }
        EXPECT_EQ(markers, 1u) << l.stems[i].role << " (" << ghost_colour_name(i) << ")";
    }
}

// One colour per role wherever a role is drawn (the start screen draws its sketch and list with the same
// role_colour): shin red, soe green, hikae blue, for the rods and the HUD's legend alike. The start
// screen once drew soe blue and hikae green.
TEST(RoleColours, TheFormsRodsAndTheHudsLegendGiveEachRoleOneColour) {
    const LessonDef l = lesson("sogetsu_basic_upright");
    const auto footprint = footprint_of(l);
    ASSERT_TRUE(footprint.ok());
    render::DrawList list;
    add_form_ghosts(list, l, *footprint, {0.0, 0.0, 0.05});
    for (std::size_t i = 0; i < l.stems.size(); ++i) {
        std::size_t drawn = 0;
        for (const auto& b : list.batches) {
            for (const auto& inst : b.instances) drawn += glm::length(glm::vec3(inst.colour) - role_colour(i).rgb) < 1e-6f ? 1 : 0;
        }
        EXPECT_GT(drawn, 0u) << l.stems[i].role << "'s rod in its colour";
    }
    EXPECT_EQ(std::string(ghost_colour_name(0)) + " " + ghost_colour_name(1) + " " + ghost_colour_name(2), "red green blue");
    LessonControls controls(l, *footprint);
    platform::PointerState g;
    g.set_letter(ghost_letter, true);
    components::FrameSnapshot frame;
    systems::TraineeChannel channel;
    (void)controls.update(g, 1, frame, channel);
    std::string legend;
    for (const auto& line : controls.hud_lines()) legend += line + "\n";
    EXPECT_NE(legend.find("shin red soe green hikae blue"), std::string::npos) << legend;
}

TEST(ModelArrangement, EachRoleIsNamedOverItsModelTipAndOverItsGhostWithItsTargetLengthAndTilt) {
    for (const char* id : {"sogetsu_basic_upright", "ikenobo_shoka_shofutai"}) {
        const LessonDef l = lesson(id);
        const auto footprint = footprint_of(l);
        ASSERT_TRUE(footprint.ok());
        const glm::dvec3 kenzan{0.01, -0.02, 0.05};
        const glm::dvec3 plate = model_plate_origin(l, kenzan);
        const auto labels = form_labels(l, *footprint, kenzan, plate);
        const Arrangement model = model_arrangement(l, *footprint);
        ASSERT_EQ(labels.size(), 2 * l.stems.size()) << id << ": a name on the model and one on the ghost, per role";
        for (std::size_t i = 0; i < l.stems.size(); ++i) {
            const auto& s = model.stems[i];
            const glm::dvec3 tip = s.path_m.empty() ? glm::dvec3(s.base_m, 0.0) + lesson_direction(s.tilt_rad, s.azimuth_rad) * s.length_m : s.path_m.back();
            const auto& on_model = labels[2 * i];
            const auto& on_ghost = labels[2 * i + 1];
            ASSERT_TRUE(on_model.anchor_m && on_ghost.anchor_m);
            EXPECT_EQ(on_model.lines, std::vector<std::string>{l.stems[i].label}) << id;
            EXPECT_LT(glm::length(glm::dvec3(*on_model.anchor_m) - (plate + tip)), 0.06) << id << " " << l.stems[i].role << ": over the model's tip";
            EXPECT_GT(on_model.anchor_m->z, (plate + tip).z) << "above it, clear of the marker";
            EXPECT_LT(glm::length(glm::dvec3(*on_ghost.anchor_m) - (kenzan + tip)), 0.04) << id << " " << l.stems[i].role << ": over the ghost's end";
            char want[96];
            std::snprintf(want, sizeof want, "%s %.0f mm, %.0f deg", s.role.c_str(), s.length_m * 1e3, s.tilt_rad * 180.0 / M_PI);
            EXPECT_EQ(on_ghost.lines, std::vector<std::string>{want});
            // In the role's colour, darker, so that white text reads on it.
            const glm::vec3 panel(on_model.panel_colour);
            for (std::size_t j = 0; j < l.stems.size(); ++j) {
                if (j == i) continue;
                EXPECT_GT(glm::length(panel - glm::vec3(labels[2 * j].panel_colour)), 0.1f) << "roles' labels differ in colour";
            }
        }
    }
}

namespace {
// The Sogetsu lesson's table as the window first shows it: the materials lying in front.
struct LessonTable {
    LessonDef l = lesson("sogetsu_basic_upright");
    std::unique_ptr<World> world;
    components::FrameSnapshot frame;
    std::size_t willow = 0;
    LessonTable() {
        auto scene = scene_for_lesson(l);
        EXPECT_TRUE(scene.ok());
        auto made = World::create(*scene);
        EXPECT_TRUE(made.ok());
        world = std::move(made).value();
        sched::DeterministicClock clock(world->schedule);
        clock.run_for_us(300'000);
        frame = world->main.resource<const systems::ReceivedFrames>()->latest();
        while (willow < frame.flowers.size() && frame.flowers[willow].species != "willow_branch") ++willow;
        EXPECT_LT(willow, frame.flowers.size());
    }
    std::string next_step(std::uint8_t hand = 1) {
        LessonControls controls(l, footprint(l));
        systems::TraineeChannel channel;
        (void)controls.update(platform::PointerState{}, hand, frame, channel);
        return controls.next_step();
    }
};
} // namespace

// What a press would take is named with the role it would play (issue 37: a tiny yellow spot lit a
// chrysanthemum while the trainee aimed at the willow); pressed mid-stem on a lying stem, the hand
// takes it by its bottom end (the window moves the mouse's hand there); a press that took nothing
// says why.
TEST(Reach, APressIsNamedWithItsStemAndRoleAndTakesALyingStemByItsBottomEnd) {
    LessonTable t;
    const auto x = t.frame.flowers[t.willow].points_m;
    ASSERT_GE(x.size(), 4u);
    auto& hand = t.frame.hands[1];
    hand.holding = false;
    hand.held_flower = -1;
    hand.position_m = x[x.size() / 2];
    const auto reach = systems::stem_in_reach(t.frame, 1);
    ASSERT_TRUE(reach.has_value());
    EXPECT_EQ(reach->flower, t.willow);
    const auto grip = bottom_grip_for(t.frame, 1);
    ASSERT_TRUE(grip.has_value()) << "mid-stem: too far from its end to push it in";
    double along = 0.0;
    for (std::size_t i = 1; i < x.size() && glm::length(x[i - 1] - *grip) > 1e-12; ++i) along += glm::length(x[i] - x[i - 1]);
    EXPECT_LT(along, 0.08) << "taken near its bottom end";
    EXPECT_GT(along, 0.045) << "above what a cut for its role takes off";
    EXPECT_EQ(t.next_step(), "hold the left button to take the willow branch for shin: the hand takes it by its bottom end");
    // The whole stem is marked, not a spot: a yellow segment along all of it.
    std::size_t yellow = 0;
    for (const auto& b : systems::build_draw_list(t.frame).batches) {
        for (const auto& inst : b.instances) yellow += glm::length(glm::vec3(inst.colour) - glm::vec3(1.0f, 0.85f, 0.1f)) < 1e-6f ? 1 : 0;
    }
    EXPECT_GE(yellow, x.size() - 3) << "every segment but the grip's";
    hand.position_m = x[1];
    EXPECT_FALSE(bottom_grip_for(t.frame, 1).has_value()) << "near its end already";
    EXPECT_EQ(t.next_step(), "hold the left button to take the willow branch for shin");
    hand.position_m = {0.0, 0.3, 0.4};
    EXPECT_EQ(t.next_step(), "take a stem: point at one (the cube goes onto it and it turns yellow) and hold the left button");
    hand.grab_button = true;
    EXPECT_EQ(t.next_step(), "nothing under the cube: release the button, point at a stem until it turns yellow, then hold it");
}

// A held stem shows where it would go in (issue 37: twice lowered in front of the kenzan, outside or
// under the container's wall, with nothing saying so): green over the pins, red past them or through
// the wall, and the panel's next step says which.
TEST(Reach, AHeldStemsEntryIsMarkedRedWhenItWouldMissThePinsOrMeetTheWall) {
    LessonTable t;
    ASSERT_TRUE(t.frame.kenzan && t.frame.container);
    const auto& k = *t.frame.kenzan;
    const double tips = k.origin_m.z + k.pin_height_m();
    auto& hand = t.frame.hands[1];
    hand.holding = true;
    hand.held_flower = static_cast<std::int32_t>(t.willow);
    auto& x = t.frame.flowers[t.willow].points_m;
    x.resize(10);
    // Upright over a point (x, y), its end 40 mm above the pin tips, leaning `lean_x` sideways a metre up.
    const auto hold_over = [&](double px, double py, double lean_x) {
        for (std::size_t i = 0; i < x.size(); ++i) {
            const double up = 0.04 * static_cast<double>(i);
            x[i] = {px + lean_x * up, py, tips + 0.04 + up};
        }
        return systems::entry_mark(t.frame, 1);
    };
    const auto over = hold_over(k.origin_m.x, k.origin_m.y, 0.0);
    ASSERT_TRUE(over.has_value());
    EXPECT_TRUE(over->good());
    EXPECT_NEAR(over->at_m.z, tips, 1e-9);
    // The panel's gauge: the stem's lean now (upright) against shin's band.
    const auto gauge = advise_held_stem(t.l, footprint(t.l), t.frame, 1).gauge;
    ASSERT_TRUE(gauge.has_value());
    EXPECT_EQ(gauge->role, 0u);
    EXPECT_NEAR(gauge->tilt_rad, 0.0, 1e-6);
    EXPECT_NEAR(gauge->target_tilt_rad, t.l.stems[0].tilt_rad.target, 1e-12);
    ASSERT_TRUE(gauge->target_azimuth_rad.has_value());
    hold_over(k.origin_m.x, k.origin_m.y, -0.3); // leaning to the viewer's left
    const auto leaning = advise_held_stem(t.l, footprint(t.l), t.frame, 1).gauge;
    ASSERT_TRUE(leaning.has_value());
    EXPECT_NEAR(leaning->tilt_rad, std::atan(0.3), 1e-6);
    EXPECT_NEAR(leaning->azimuth_rad, M_PI / 2, 1e-6) << "lesson convention: + to the viewer's left";
    const auto beside = hold_over(k.pin_base(k.columns - 1, 0).x + 0.03, k.origin_m.y, 0.0);
    ASSERT_TRUE(beside.has_value());
    EXPECT_FALSE(beside->on_pins);
    EXPECT_NE(t.next_step().find("the red ring shows it would miss the pins"), std::string::npos) << t.next_step();
    // Its end outside the rim, slanting in toward the kenzan: lowered, its end lands on the table.
    const auto& c = *t.frame.container;
    const double outside_x = c.centre_m.x + c.half_extent_m.x + 0.02;
    for (std::size_t i = 0; i < x.size(); ++i) x[i] = {outside_x - 0.06 * static_cast<double>(i), k.origin_m.y, c.rim_z_m + 0.01 + 0.04 * static_cast<double>(i)};
    const auto outside = systems::entry_mark(t.frame, 1);
    ASSERT_TRUE(outside.has_value());
    EXPECT_FALSE(outside->on_pins);
    // Its end over the pins' edge nearest the wall, leaning steeply toward the wall: it would stand
    // through the wall (a trainee's soe did), red, and said so.
    const glm::dvec3 edge_pin = k.pin_base(0, 0); // the front left pin
    const glm::dvec2 out_dir = glm::normalize(glm::dvec2(edge_pin) - c.centre_m);
    const auto lean_toward = [&](glm::dvec2 dir, double tilt_rad) {
        const glm::dvec3 u{dir.x * std::sin(tilt_rad), dir.y * std::sin(tilt_rad), std::cos(tilt_rad)};
        for (std::size_t i = 0; i < x.size(); ++i) x[i] = glm::dvec3(edge_pin.x, edge_pin.y, tips + 0.03) + u * (0.04 * static_cast<double>(i));
        return systems::entry_mark(t.frame, 1);
    };
    const auto through = lean_toward(out_dir, 70.0 * M_PI / 180.0);
    ASSERT_TRUE(through.has_value()) << "a low stem has a ring too (past 60 degrees it had none)";
    EXPECT_TRUE(through->on_pins);
    EXPECT_TRUE(through->meets_wall);
    EXPECT_NEAR(glm::dot(glm::dvec2(through->at_m - edge_pin), out_dir), k.pin_height_m() * std::tan(70.0 * M_PI / 180.0), 1e-6)
        << "the ring where it comes out of the pins, along its lean";
    EXPECT_GT(through->rim_tilt_rad, 0.0);
    EXPECT_LT(through->rim_tilt_rad, 70.0 * M_PI / 180.0);
    // Told by how much less, against the lean of its lower part (a curved soe read "at most 50°" while
    // its gauge, the whole line's, showed 45).
    EXPECT_NEAR(through->lower_tilt_rad, 70.0 * M_PI / 180.0, 1e-9);
    const double less_deg = std::ceil(70.0 - through->rim_tilt_rad * 180.0 / M_PI);
    EXPECT_EQ(t.next_step().rfind("lean it " + std::to_string(static_cast<int>(less_deg)) + "° less here (it would go through the container's wall, or rest on its rim)", 0), 0u)
        << t.next_step();
    // Leant that far, it clears the rim: the ring is green.
    const auto at_rim = lean_toward(out_dir, through->rim_tilt_rad - 0.01);
    ASSERT_TRUE(at_rim.has_value());
    EXPECT_FALSE(at_rim->meets_wall);
    // The same place leaning the other way, toward the middle: good.
    const auto inward = lean_toward(-out_dir, 70.0 * M_PI / 180.0);
    ASSERT_TRUE(inward.has_value());
    EXPECT_TRUE(inward->good());
    // Too short to reach the wall, leaning at it the same: nothing in its way (a 59 mm jushi was told to
    // lean less).
    {
        const double tilt = 70.0 * M_PI / 180.0;
        const glm::dvec3 u{out_dir.x * std::sin(tilt), out_dir.y * std::sin(tilt), std::cos(tilt)};
        for (std::size_t i = 0; i < x.size(); ++i) x[i] = glm::dvec3(edge_pin.x, edge_pin.y, tips + 0.03) + u * (0.012 * static_cast<double>(i) / static_cast<double>(x.size() - 1));
        const auto short_one = systems::entry_mark(t.frame, 1);
        ASSERT_TRUE(short_one.has_value());
        EXPECT_FALSE(short_one->meets_wall);
    }
    // Wholly outside the container, its way down ends on the table: it misses the pins, no wall.
    for (std::size_t i = 0; i < x.size(); ++i) x[i] = {outside_x + 0.03, k.origin_m.y, c.rim_z_m + 0.01 + 0.04 * static_cast<double>(i)};
    const auto beside_it = systems::entry_mark(t.frame, 1);
    ASSERT_TRUE(beside_it.has_value());
    EXPECT_FALSE(beside_it->meets_wall);
    EXPECT_FALSE(beside_it->on_pins);
    // Held nearly flat (83 degrees), no ring far off.
    for (std::size_t i = 0; i < x.size(); ++i) x[i] = {k.origin_m.x + 0.04 * static_cast<double>(i), k.origin_m.y, tips + 0.05 + 0.005 * static_cast<double>(i)};
    EXPECT_FALSE(systems::entry_mark(t.frame, 1).has_value());
}

// A trainee's stems all lost their place points with no word while placing them: held at its role's
// tilt with the ring on the pins but outside the role's part of the kenzan, the next step says where to
// move it, in words; over its part, it says to lower it.
TEST(Reach, AHeldStemOverTheWrongPartOfTheKenzanIsToldWhereItsRoleGoes) {
    LessonTable t;
    auto& hand = t.frame.hands[1];
    hand.holding = true;
    hand.held_flower = static_cast<std::int32_t>(t.willow);
    auto& x = t.frame.flowers[t.willow].points_m;
    const auto& k = *t.frame.kenzan;
    const double tips = k.origin_m.z + k.pin_height_m();
    const double length = 0.440; // cut for shin already
    const auto over = [&](double px, double py) {
        // 15° toward the left front (lesson azimuth 45°: -x, -y), its end 30 mm over the pin tips.
        const double t15 = 15.0 * M_PI / 180.0;
        const glm::dvec3 u{-std::sin(t15) * M_SQRT1_2, -std::sin(t15) * M_SQRT1_2, std::cos(t15)};
        for (std::size_t i = 0; i < x.size(); ++i) x[i] = glm::dvec3(px, py, tips + 0.03) + u * (length * static_cast<double>(i) / static_cast<double>(x.size() - 1));
        hand.position_m = x[2];
        return t.next_step();
    };
    EXPECT_EQ(over(k.origin_m.x + 0.025, k.origin_m.y - 0.025), "move it toward the back left of the kenzan: the ring is in the front right, shin goes in the back left");
    // Over its part at its lean: the tilt is done, so Next moves on to lowering it (issue 59: at 69-70°
    // with the ring green it still said "tilt it 69°").
    EXPECT_EQ(over(k.origin_m.x - 0.02, k.origin_m.y + 0.025).rfind("its lean is right (15°): lower it straight down into the back left of the kenzan", 0), 0u)
        << over(k.origin_m.x - 0.02, k.origin_m.y + 0.025);
    // Upright there, the tilt is still to do.
    const auto upright = [&] {
        for (std::size_t i = 0; i < x.size(); ++i) x[i] = glm::dvec3(k.origin_m.x - 0.02, k.origin_m.y + 0.025, tips + 0.03 + length * static_cast<double>(i) / static_cast<double>(x.size() - 1));
        hand.position_m = x[2];
        return t.next_step();
    }();
    EXPECT_EQ(upright.rfind("tilt it 15° toward the left front (Ctrl+drag), then lower it into the back left of the kenzan", 0), 0u) << upright;
}

// Issue 59 item 4: supporting stems let go at 55° sank to 78° with no word. Held in the pins at a lean
// they cannot hold, the next step says so before the hand lets go, with the lean they would hold there.
TEST(Reach, AHeldStemInThePinsAtALeanTheyCannotHoldIsSaidBeforeItIsLetGo) {
    LessonTable t;
    auto& hand = t.frame.hands[1];
    hand.holding = true;
    hand.held_flower = static_cast<std::int32_t>(t.willow);
    auto& f = t.frame.flowers[t.willow];
    auto& x = f.points_m;
    const auto& k = *t.frame.kenzan;
    const double t55 = 55.0 * M_PI / 180.0;
    const glm::dvec3 u{0.0, -std::sin(t55), std::cos(t55)};
    for (std::size_t i = 0; i < x.size(); ++i) x[i] = glm::dvec3(k.origin_m.x, k.origin_m.y, k.origin_m.z + 0.005) + u * (0.3 * static_cast<double>(i) / static_cast<double>(x.size() - 1));
    hand.position_m = x[2];
    f.in_kenzan = true;
    f.fallen = false;
    f.depth_m = 0.012; // deep enough: a shallow stem is told to go deeper first
    f.gravity_moment_nm = 0.020;
    f.holding_moment_nm = 0.010;
    const std::string said = t.next_step();
    EXPECT_EQ(said.rfind("let go now and it sinks: at 55° the pins hold 50 % of what its weight asks; here they hold it to about 24°", 0), 0u) << said;
    f.holding_moment_nm = 0.025; // held: nothing said of sinking
    EXPECT_EQ(t.next_step().find("sinks"), std::string::npos) << t.next_step();
}

// Held low against the container's wall, the hand stops while the mouse goes on: the next step says
// what stops it and what to do, not to move it over the kenzan.
TEST(Reach, AHeldStemHeldBackByTheWallIsToldToGoOverTheRim) {
    LessonTable t;
    auto& hand = t.frame.hands[1];
    hand.holding = true;
    hand.held_flower = static_cast<std::int32_t>(t.willow);
    hand.position_m = t.frame.flowers[t.willow].points_m[3];
    hand.device_m = hand.position_m + glm::dvec3{0.0, 0.06, 0.0};
    EXPECT_EQ(t.next_step(), "the container's wall is in the way: lift it over the rim (move the mouse up), then move it in");
    hand.device_m = hand.position_m + glm::dvec3{0.0, 0.0, -0.06}; // held up by the table: not the wall
    EXPECT_EQ(t.next_step().find("wall"), std::string::npos) << t.next_step();
}

// A trainee's shin, let go at 15° (in its band), sank to 30° and was scored there with no word: a stem
// let go in the pins that sinks more than a few degrees past its lean, out of its role's band, is named
// in the next step, with how deep it is and what to do; one that stays, or stays in its band, is not,
// nor is one still held.
TEST(Reach, AStemThatSinksOnceLetGoIsSaidToHaveSunk) {
    LessonTable t;
    LessonControls controls(t.l, footprint(t.l));
    systems::TraineeChannel channel;
    auto& hand = t.frame.hands[1];
    auto& f = t.frame.flowers[t.willow];
    const auto& k = *t.frame.kenzan;
    const auto lean = [&](double tilt_deg) {
        const glm::dvec3 u{-std::sin(tilt_deg * M_PI / 180.0), 0.0, std::cos(tilt_deg * M_PI / 180.0)};
        for (std::size_t i = 0; i < f.points_m.size(); ++i) f.points_m[i] = k.origin_m + u * (0.04 * static_cast<double>(i));
    };
    f.in_kenzan = true;
    f.depth_m = 0.004;
    lean(15.0);
    hand.holding = true;
    hand.held_flower = static_cast<std::int32_t>(t.willow);
    (void)controls.update(platform::PointerState{}, 1, t.frame, channel);
    EXPECT_EQ(controls.next_step(), "it is only 4 mm deep in the pins (they are 13 mm tall): push it down (move the mouse down) before you let go");
    f.depth_m = 0.010;
    (void)controls.update(platform::PointerState{}, 1, t.frame, channel);
    EXPECT_NE(controls.next_step().find("it is in the pins, 10 mm deep"), std::string::npos) << controls.next_step();
    f.depth_m = 0.004;
    hand.holding = false;
    hand.held_flower = -1;
    lean(18.0); // settles a little: not said
    (void)controls.update(platform::PointerState{}, 1, t.frame, channel);
    EXPECT_EQ(controls.next_step().find("sank"), std::string::npos) << controls.next_step();
    lean(24.0); // further, but still in shin's 15° ±10°: nothing to take it again for
    (void)controls.update(platform::PointerState{}, 1, t.frame, channel);
    EXPECT_EQ(controls.next_step().find("sank"), std::string::npos) << controls.next_step();
    lean(30.0);
    (void)controls.update(platform::PointerState{}, 1, t.frame, channel);
    EXPECT_EQ(controls.next_step(),
              "shin sank from 15° to 30° once let go (4 mm deep in the pins): take it again and push it deeper, or set it 15° steeper than you want it");
    f.depth_m = 0.013; // as deep as the pins go: pushing deeper is no help
    (void)controls.update(platform::PointerState{}, 1, t.frame, channel);
    EXPECT_EQ(controls.next_step(), "shin sank from 15° to 30° once let go (13 mm deep in the pins): take it again and set it 15° steeper than you want it");
    // Taken again, the word goes.
    hand.holding = true;
    hand.held_flower = static_cast<std::int32_t>(t.willow);
    (void)controls.update(platform::PointerState{}, 1, t.frame, channel);
    EXPECT_EQ(controls.next_step().find("sank"), std::string::npos) << controls.next_step();
}

// A first-time trainee saw G's rods for soe and hikae go through the suiban's wall: the form's 75° for
// hikae from the front of the kenzan crosses the wall below the rim. Drawn with the frame's container,
// each rod, from where its line crosses the pins' tops, stays inside it below the rim (hikae at the
// lean the rim allows, which its label says); drawn without it, hikae's went through.
TEST(ModelArrangement, TheFormsRodsOverTheKenzanStayInsideTheContainersWall) {
    LessonTable t;
    const auto fp = footprint(t.l);
    const auto& c = *t.frame.container;
    const auto through_wall = [&](const render::DrawList& list) {
        std::size_t crossing = 0;
        for (const auto& b : list.batches) {
            if (b.mesh != "cylinder") continue;
            for (const auto& inst : b.instances) {
                const glm::dvec3 from(inst.model[3]), along(inst.model[2]);
                for (int k = 0; k <= 50; ++k) {
                    const glm::dvec3 p = from + along * (k / 50.0);
                    if (p.z < c.rim_z_m && glm::length(glm::dvec2(p) - c.centre_m) > c.half_extent_m.x) {
                        ++crossing;
                        break;
                    }
                }
            }
        }
        return crossing;
    };
    render::DrawList bare, set;
    add_form_ghosts(bare, t.l, fp, t.frame.kenzan->origin_m);
    add_form_ghosts(set, t.l, fp, t.frame.kenzan->origin_m, &t.frame);
    ASSERT_TRUE(c.round);
    EXPECT_GT(through_wall(bare), 0u) << "the form's own leans cross the wall";
    EXPECT_EQ(through_wall(set), 0u);
    const auto labels = form_labels(t.l, fp, t.frame.kenzan->origin_m, model_plate_origin(t.l, t.frame.kenzan->origin_m), &t.frame);
    std::string all;
    for (const auto& label : labels) all += label.lines.front() + "\n";
    EXPECT_NE(all.find("hikae 245 mm, 69 deg"), std::string::npos) << all;
}

// Hovering over hikae standing in the kenzan, a trainee read "take the chrysanthemum for a supporting
// stem (jushi): it comes out of the pins". A stem that stands says the role it plays there.
TEST(Reach, AStemStandingInTheKenzanIsNamedByTheRoleItPlays) {
    LessonTable t;
    auto& f = t.frame.flowers[t.willow];
    const auto& k = *t.frame.kenzan;
    const glm::dvec3 lean{-std::sin(15.0 * M_PI / 180.0) * 0.7071, -std::sin(15.0 * M_PI / 180.0) * 0.7071, std::cos(15.0 * M_PI / 180.0)};
    for (std::size_t i = 0; i < f.points_m.size(); ++i) f.points_m[i] = k.origin_m + glm::dvec3{-0.02, 0.02, 0.0} + lean * (0.45 * static_cast<double>(i) / static_cast<double>(f.points_m.size() - 1));
    f.in_kenzan = true;
    f.depth_m = 0.012;
    auto& hand = t.frame.hands[1];
    hand.position_m = f.points_m[f.points_m.size() / 2];
    const std::string says = t.next_step();
    EXPECT_NE(says.find("shin stands; hold the left button to take the willow branch (it stands as shin): it comes out of the pins"), std::string::npos) << says;
}

// With shin, soe and hikae standing, the next step said "every role stands: Score (Enter)" and a trainee
// never added the jushi the score then asked for. A rule still unmet is the next thing to do.
TEST(Reach, WithEveryMainRoleStandingAnUnmetRuleIsTheNextStep) {
    LessonTable t;
    stand_as_model(t.frame, t.l, "shin", "willow_branch");
    stand_as_model(t.frame, t.l, "soe", "cherry_branch");
    stand_as_model(t.frame, t.l, "hikae", "chrysanthemum");
    t.frame.hands[1].position_m = {0.0, 0.3, 0.4};
    const std::string says = t.next_step();
    EXPECT_EQ(says.rfind("shin, soe, hikae stand; to do: the kenzan still shows from the front", 0), 0u) << says;
    EXPECT_NE(says.find("add a low supporting stem"), std::string::npos) << says;
    EXPECT_NE(says.find("; or Score (Enter)"), std::string::npos) << says;
}

// A first-time trainee spent six minutes looking for the two leaves the score said were under the water,
// and stripped the wrong ones. Leaves under the container's water are drawn in their own colour; the
// same stem on the table, its leaves as they are.
TEST(Reach, LeavesUnderTheContainersWaterAreDrawnInTheirOwnColour) {
    LessonTable t;
    std::size_t chrysanthemum = 0;
    while (chrysanthemum < t.frame.flowers.size() && t.frame.flowers[chrysanthemum].species != "chrysanthemum") ++chrysanthemum;
    ASSERT_LT(chrysanthemum, t.frame.flowers.size());
    auto& f = t.frame.flowers[chrysanthemum];
    const auto& c = *t.frame.container;
    ASSERT_GT(c.water_z_m, c.floor_z_m);
    const glm::vec3 rotting{0.9f, 0.35f, 0.05f};
    const auto count = [&] {
        std::size_t n = 0;
        for (const auto& b : systems::build_draw_list(t.frame).batches) {
            for (const auto& inst : b.instances) n += glm::length(glm::vec3(inst.colour) - rotting) < 1e-6f ? 1 : 0;
        }
        return n;
    };
    EXPECT_EQ(count(), 0u) << "on the table, none";
    // Stood upright in the kenzan, its lowest leaves under the water.
    const glm::dvec3 at = t.frame.kenzan->origin_m;
    for (std::size_t i = 0; i < f.points_m.size(); ++i) f.points_m[i] = at + glm::dvec3{0.0, 0.0, 0.1 * static_cast<double>(i) / static_cast<double>(f.points_m.size() - 1)};
    std::size_t leaves_below = 0;
    for (const auto& part : f.parts) leaves_below += part.kind == components::PartKind::leaf && f.points_m[std::min<std::size_t>(part.stem_point, f.points_m.size() - 1)].z < c.water_z_m ? 1 : 0;
    ASSERT_GT(leaves_below, 0u) << "the test stands it with leaves in the water";
    EXPECT_EQ(count(), leaves_below);
}

// A first-time trainee leant shin in the pins until it came out of them, let go, and it toppled with no
// word (a stem out of the kenzan is not "fallen"; it lies like the materials on the table). Let go over
// the container but not in the pins, it is said to have fallen; let go away from it, nothing is said.
TEST(Reach, AStemLetGoOverTheContainerButNotInThePinsIsSaidToHaveFallen) {
    LessonTable t;
    LessonControls controls(t.l, footprint(t.l));
    systems::TraineeChannel channel;
    auto& hand = t.frame.hands[1];
    auto& f = t.frame.flowers[t.willow];
    const auto& k = *t.frame.kenzan;
    for (std::size_t i = 0; i < f.points_m.size(); ++i) f.points_m[i] = k.origin_m + glm::dvec3{0.0, 0.0, 0.03 + 0.04 * static_cast<double>(i)};
    f.in_kenzan = false;
    hand.holding = true;
    hand.held_flower = static_cast<std::int32_t>(t.willow);
    (void)controls.update(platform::PointerState{}, 1, t.frame, channel);
    hand.holding = false;
    hand.held_flower = -1;
    (void)controls.update(platform::PointerState{}, 1, t.frame, channel);
    EXPECT_EQ(controls.next_step(), "shin was not in the pins when you let go, and fell: take it again, push it down into the pins, then let go");
    {
        // Tab to the other hand is no letting go: the right hand still holds it.
        LessonControls tabbed(t.l, footprint(t.l));
        hand.holding = true;
        hand.held_flower = static_cast<std::int32_t>(t.willow);
        (void)tabbed.update(platform::PointerState{}, 1, t.frame, channel);
        (void)tabbed.update(platform::PointerState{}, 0, t.frame, channel);
        EXPECT_EQ(tabbed.next_step().find("fell"), std::string::npos) << tabbed.next_step();
        hand.holding = false;
        hand.held_flower = -1;
    }
    // Taken again, the word goes; let go on the table in front, nothing is said.
    hand.holding = true;
    hand.held_flower = static_cast<std::int32_t>(t.willow);
    (void)controls.update(platform::PointerState{}, 1, t.frame, channel);
    for (auto& p : f.points_m) p += glm::dvec3{0.0, -0.3, 0.0};
    hand.holding = false;
    hand.held_flower = -1;
    (void)controls.update(platform::PointerState{}, 1, t.frame, channel);
    EXPECT_EQ(controls.next_step().find("fell"), std::string::npos) << controls.next_step();
}

// The result in the panel (issue 37: numbers and coordinates a beginner cannot act on): per stem a bar
// for each criterion, full where it is within its band; where it lost points, the tip in plain
// directions without coordinates, and the stem's heading in its role's colour.
TEST(ResultPanel, EachStemHasABarPerCriterionAndATipInPlainDirectionsWhereItLostPoints) {
    const LessonDef l = lesson("sogetsu_basic_upright");
    Arrangement a = model_arrangement(l, footprint(l));
    stem_with_role(a, "shin")->tilt_rad = 45 * deg;
    stem_with_role(a, "soe")->base_m += glm::dvec2{0.03, -0.03}; // off its place on the kenzan
    const auto scored = score_form(l, a, footprint(l));
    ASSERT_TRUE(scored.ok());
    SessionPanelModel model;
    show_score(model, *scored, &l);
    ASSERT_TRUE(model.score.has_value());
    EXPECT_DOUBLE_EQ(*model.score, scored->score);
    ASSERT_EQ(model.stems.size(), 3u);
    const auto& shin = model.stems[0];
    EXPECT_EQ(shin.role, "shin");
    EXPECT_EQ(shin.colour, role_colour(0).rgb);
    const auto tilt = std::find_if(shin.bars.begin(), shin.bars.end(), [](const auto& b) { return b.label.rfind("tilt ", 0) == 0; });
    ASSERT_NE(tilt, shin.bars.end());
    EXPECT_FLOAT_EQ(tilt->fraction, 0.0f);
    EXPECT_EQ(tilt->tip, "45° from vertical, the form wants 15° ±10°, 20° outside it: raise it 30° toward upright");
    for (const auto& b : shin.bars) {
        if (&b != &*tilt) {
            EXPECT_TRUE(b.tip.empty() && b.fraction == 1.0f) << b.label << ": " << b.tip;
        }
    }
    const auto& soe = model.stems[1];
    const auto place = std::find_if(soe.bars.begin(), soe.bars.end(), [](const auto& b) { return b.label.rfind("place ", 0) == 0; });
    ASSERT_NE(place, soe.bars.end());
    EXPECT_LT(place->fraction, 1.0f);
    EXPECT_NE(place->tip.find("move its base"), std::string::npos) << place->tip;
    EXPECT_NE(place->tip.find("mm toward the front left"), std::string::npos) << place->tip;
    for (const auto& s : model.stems) {
        for (const auto& b : s.bars) EXPECT_EQ(b.tip.find("x ="), std::string::npos) << b.tip << ": no coordinates";
    }
    EXPECT_EQ(model.rules.size(), scored->rules.size());
}

// The next step follows the lesson (a first-time trainee's session: nothing said a stem was in the
// pins, nor what stood, and after Enter the line still asked for a stem).
TEST(Reach, TheNextStepSaysWhenAStemIsInThePinsAndWhatToDoAfterTheScore) {
    LessonTable t;
    auto& hand = t.frame.hands[1];
    hand.holding = true;
    hand.held_flower = static_cast<std::int32_t>(t.willow);
    t.frame.flowers[t.willow].in_kenzan = true;
    t.frame.flowers[t.willow].depth_m = 0.012;
    EXPECT_EQ(t.next_step(), "it is in the pins, 12 mm deep: release the button to let go of it (click, if the button is up)");
    hand.holding = false;
    hand.held_flower = -1;
    hand.position_m = {0.0, 0.3, 0.4};
    LessonControls controls(t.l, footprint(t.l));
    systems::TraineeChannel channel;
    platform::PointerState enter;
    enter.finish_key = true;
    const auto effects = controls.update(enter, 1, t.frame, channel);
    ASSERT_TRUE(effects.score.has_value());
    EXPECT_EQ(controls.next_step().rfind("scored: ", 0), 0u) << controls.next_step();
    hand.holding = true; // a stem taken again: the lesson goes on
    (void)controls.update(platform::PointerState{}, 1, t.frame, channel);
    EXPECT_EQ(controls.next_step().rfind("scored: ", 0), std::string::npos) << controls.next_step();
}

// Issue 41: in Sogetsu the jushi hide the kenzan, not the main stems. The model arrangement without
// its supporting stems (hikae low in front, which once earned "hidden (94 %)" on its own) fails the
// rule, and the tip asks for a supporting stem.
TEST(FormScore, InSogetsuTheMainStemsDoNotHideTheKenzanTheJushiDo) {
    const LessonDef l = lesson("sogetsu_basic_upright");
    Arrangement a = model_arrangement(l, footprint(l));
    ASSERT_GE(std::count_if(a.stems.begin(), a.stems.end(), [](const ArrangementStem& s) { return s.role == "supporting"; }), 2);
    const auto with = score_form(l, a, footprint(l));
    ASSERT_TRUE(with.ok());
    EXPECT_TRUE(rule(*with, "kenzan_hidden_front")->ok) << rule(*with, "kenzan_hidden_front")->tip;
    std::erase_if(a.stems, [](const ArrangementStem& s) { return s.role == "supporting"; });
    // Hikae laid low right across the front: still not a jushi.
    stem_with_role(a, "hikae")->tilt_rad = 80 * deg;
    stem_with_role(a, "hikae")->azimuth_rad = 0.0;
    const auto without = score_form(l, a, footprint(l));
    ASSERT_TRUE(without.ok());
    const RuleResult* hidden = rule(*without, "kenzan_hidden_front");
    ASSERT_NE(hidden, nullptr);
    EXPECT_FALSE(hidden->ok);
    EXPECT_EQ(hidden->tip.rfind("the kenzan still shows from the front: the supporting stems hide 0 % of its width", 0), 0u) << hidden->tip;
}

// A stem leaning out of its part of the kenzan crosses the pins' tops beyond the kenzan's edge (a hikae
// at 70 degrees, 36 mm out): it is in its part, not "17 mm outside the front right; move it toward the
// front right". Inward, past the middle line, it is outside.
TEST(FormScore, AStemLeaningOutOfItsPartPastTheKenzansEdgeIsInItsPart) {
    const LessonDef l = lesson("sogetsu_basic_upright");
    Arrangement a = model_arrangement(l, footprint(l));
    ArrangementStem* hikae = stem_with_role(a, "hikae");
    const glm::dvec2 half = 0.5 * footprint(l).size_m;
    hikae->base_m = {half.x + 0.017, -half.y - 0.017};
    const auto beyond = score_form(l, a, footprint(l));
    ASSERT_TRUE(beyond.ok());
    const Criterion* place = criterion(*beyond, "hikae", "region_mm");
    ASSERT_NE(place, nullptr);
    EXPECT_DOUBLE_EQ(place->points, place->max_points) << place->tip;
    EXPECT_EQ(place->tip.find("move"), std::string::npos) << place->tip;
    hikae->base_m = {-0.015, -0.02};
    const auto inward = score_form(l, a, footprint(l));
    EXPECT_LT(criterion(*inward, "hikae", "region_mm")->points, criterion(*inward, "hikae", "region_mm")->max_points);
    EXPECT_NE(criterion(*inward, "hikae", "region_mm")->tip.find("move its base 11 mm toward the front right"), std::string::npos)
        << criterion(*inward, "hikae", "region_mm")->tip;
}

// Sogetsu teaches hikae at 3/4 of soe, and at 1/2: a hikae at half of soe keeps its length points
// (it lost all of them), scored against the ratio it is nearest, and the tip names that ratio.
TEST(FormScore, HikaeAtHalfOfSoeAPublishedAlternativeKeepsItsLengthPoints) {
    const LessonDef l = lesson("sogetsu_basic_upright");
    Arrangement a = model_arrangement(l, footprint(l));
    const double soe = stem_with_role(a, "soe")->length_m;
    stem_with_role(a, "hikae")->length_m = 0.5 * soe;
    const auto scored = score_form(l, a, footprint(l));
    ASSERT_TRUE(scored.ok());
    const Criterion* length = criterion(*scored, "hikae", "length_mm");
    ASSERT_NE(length, nullptr);
    EXPECT_DOUBLE_EQ(length->points, length->max_points) << length->tip;
    EXPECT_NE(length->tip.find("(0.50 × soe"), std::string::npos) << length->tip;
    // Between the two (0.62 of soe) it is outside both bands and keeps little.
    stem_with_role(a, "hikae")->length_m = 0.62 * soe;
    const auto between = score_form(l, a, footprint(l));
    EXPECT_LT(criterion(*between, "hikae", "length_mm")->points, 0.3 * length->max_points + 1e-9);
    // Outside both, the tip names both: a trainee who cut for 3/4 and is judged against 1/2 learns
    // what 3/4 wanted too (it said only "cut it 40 mm shorter").
    const std::string tip = criterion(*between, "hikae", "length_mm")->tip;
    const double nearest = std::round(soe * 1e3 * 0.5), other = std::round(soe * 1e3 * 0.75), at = std::round(0.62 * soe * 1e3);
    const auto fmt = [](const char* f, double v) {
        char text[120];
        std::snprintf(text, sizeof text, f, v);
        return std::string(text);
    };
    EXPECT_NE(tip.find(fmt("wants %.0f mm", nearest)), std::string::npos) << tip;
    EXPECT_NE(tip.find(fmt("; the form also takes %.0f mm (0.75 × soe, ", other)), std::string::npos) << tip;
    EXPECT_NE(tip.find(fmt("for that it is %.0f mm short", other - at)), std::string::npos) << tip;
    // Within a band, no other ratio is spoken of.
    EXPECT_EQ(length->tip.find("also takes"), std::string::npos) << length->tip;
}

// What a tip says and what the bar gives agree: the shoka's tai at 47.4 degrees was "47°, 0° outside"
// in words and lost points; judged on the whole degrees shown, 47 is within 35 +-12 and full.
TEST(FormScore, ACriterionIsJudgedOnTheWholeDegreesItsTipShows) {
    const LessonDef l = lesson("ikenobo_shoka_shofutai");
    Arrangement a = model_arrangement(l, footprint(l));
    ArrangementStem* tai = stem_with_role(a, "tai");
    ASSERT_NE(tai, nullptr);
    tai->path_m.clear();
    tai->tilt_rad = 47.4 * deg;
    auto scored = score_form(l, a, footprint(l));
    ASSERT_TRUE(scored.ok());
    const Criterion* tilt = criterion(*scored, "tai", "tilt_deg");
    EXPECT_DOUBLE_EQ(tilt->points, tilt->max_points) << tilt->tip;
    EXPECT_NE(tilt->tip.find("47° from vertical, within"), std::string::npos) << tilt->tip;
    tai->tilt_rad = 47.6 * deg;
    scored = score_form(l, a, footprint(l));
    tilt = criterion(*scored, "tai", "tilt_deg");
    EXPECT_NEAR(tilt->points, tilt->max_points * 0.3 * (1.0 - 1.0 / 12.0), 1e-9) << tilt->tip;
    EXPECT_NE(tilt->tip.find("48° from vertical, the form wants 35° ±12°, 1° outside it"), std::string::npos) << tilt->tip;
}

// The start screen's table lists what the rules score: Sogetsu's jushi, with what they are for, and
// both of hikae's ratios.
TEST(FormTable, TheStartScreensTableListsTheJushiARuleScoresAndHikaesTwoRatios) {
    const auto rows = form_table(lesson("sogetsu_basic_upright"));
    ASSERT_EQ(rows.size(), 4u);
    EXPECT_EQ(rows[2].stem, "Hikae (earth)");
    EXPECT_NE(rows[2].length.find("(0.75 or 0.5 x Soe (person) as cut)"), std::string::npos) << rows[2].length;
    EXPECT_TRUE(rows[3].supporting);
    EXPECT_EQ(rows[3].stem, "Jushi (supporting)");
    EXPECT_EQ(rows[3].length, "shorter than Shin (heaven), up to 4");
    EXPECT_EQ(rows[3].tilt, "45 deg or more");
    EXPECT_EQ(rows[3].leaning, "front, hiding 80 % of the kenzan");
    const auto shoka = form_table(lesson("ikenobo_shoka_shofutai"));
    EXPECT_EQ(shoka.size(), 3u) << "no supporting stems in a shoka";
    EXPECT_EQ(form_table(lesson("ohara_rising_form")).back().stem, "Fillers (chukan-shi)");
}

// The lesson format's new fields: other ratios a school teaches, and who hides the kenzan; each
// wrong value named by its JSON path.
TEST(LessonFormat, OtherRatiosAndWhoHidesTheKenzanAreReadAndCheckedByField) {
    const auto good = parse_lesson(lesson_text([](nlohmann::json& j) {
                                       j["main_stems"][1]["length"]["also"] = {0.75};
                                       j["rules"] = {{{"rule", "kenzan_hidden_front"}, {"by", "supporting"}}};
                                   }),
                                   "t.json");
    ASSERT_TRUE(good.ok()) << good.error().message;
    ASSERT_EQ(good->stems[1].length_also.size(), 1u);
    EXPECT_DOUBLE_EQ(good->stems[1].length_also[0], 0.75);
    EXPECT_TRUE(good->rules[0].supporting_only);
    const auto bad_ratio = parse_lesson(lesson_text([](nlohmann::json& j) { j["main_stems"][1]["length"]["also"] = {0.75, "half"}; }), "t.json");
    ASSERT_FALSE(bad_ratio.ok());
    EXPECT_NE(bad_ratio.error().message.find("/main_stems/1/length/also/1: expected a ratio in [0.05, 10], got \"half\""), std::string::npos)
        << bad_ratio.error().message;
    const auto bad_by = parse_lesson(lesson_text([](nlohmann::json& j) { j["rules"] = {{{"rule", "kenzan_hidden_front"}, {"by", "main"}}}; }), "t.json");
    ASSERT_FALSE(bad_by.ok());
    EXPECT_NE(bad_by.error().message.find("/rules/0/by"), std::string::npos) << bad_by.error().message;
    const auto by_elsewhere = parse_lesson(lesson_text([](nlohmann::json& j) { j["rules"] = {{{"rule", "no_crossing_front"}, {"by", "supporting"}}}; }), "t.json");
    EXPECT_FALSE(by_elsewhere.ok()) << "only the kenzan rule knows 'by'";
}
