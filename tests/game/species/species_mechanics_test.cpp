#include <gtest/gtest.h>

#include <filesystem>

#include "engine/assets/files.hpp"
#include "game/world/species_mechanics.hpp"

using namespace ikebana;
using namespace ikebana::game;

namespace {
std::filesystem::path shipped(const std::string& id) { return std::filesystem::path(IKEBANA_ASSET_DIR) / "species" / (id + ".json"); }

// The chrysanthemum with its stem's Young's modulus divided by `softer`, in a folder of the test's own.
std::filesystem::path softened(double softer) {
    auto text = *assets::read_text_file(shipped("chrysanthemum"));
    const std::string from = "\"youngs_modulus_mpa\": 400";
    const auto at = text.find(from);
    EXPECT_NE(at, std::string::npos);
    text.replace(at, from.size(), "\"youngs_modulus_mpa\": " + std::to_string(400.0 / softer));
    const auto dir = std::filesystem::temp_directory_path() / ("ikebana-mechanics-" + std::to_string(softer));
    std::filesystem::create_directories(dir);
    const auto file = dir / "chrysanthemum.json"; // its id is the file's name
    EXPECT_TRUE(assets::write_text_file(file, text));
    return file;
}
} // namespace

// The designer's numbers are the simulator's: a shipped flower set upright stands with room to spare,
// leaning less than it was set at plus a little, and the same trial twice gives the same numbers.
TEST(SpeciesMechanics, AShippedFlowerSetUprightStandsAndTheTrialsRepeat) {
    const auto m = species_mechanics(shipped("chrysanthemum"));
    ASSERT_TRUE(m) << m.error().message;
    ASSERT_EQ(m->stands.size(), 3u);
    EXPECT_EQ(m->stands[0].set_at_deg, 0.0);
    EXPECT_TRUE(m->stands[0].stands);
    EXPECT_LT(m->stands[0].tilt_deg, 15.0);
    EXPECT_GT(m->stands[0].margin(), 1.0);
    EXPECT_GT(m->stands[1].tilt_deg, m->stands[0].tilt_deg) << "set at 45 leans more than set upright";
    EXPECT_EQ(m->scenes.size(), 4u) << "three stands and the sag, each with its picture's frame";
    const auto again = species_mechanics(shipped("chrysanthemum"));
    ASSERT_TRUE(again);
    EXPECT_EQ(again->sag.tip_drop_mm, m->sag.tip_drop_mm);
    EXPECT_EQ(again->stands[1].tilt_deg, m->stands[1].tilt_deg);
}

// What a designer changes shows: a stem ten times softer sags further held level, and leans further
// set at 45 degrees.
TEST(SpeciesMechanics, ASofterStemSagsFurtherHeldLevel) {
    const auto stiff = species_mechanics(shipped("chrysanthemum"));
    const auto soft = species_mechanics(softened(10.0));
    ASSERT_TRUE(stiff) << stiff.error().message;
    ASSERT_TRUE(soft) << soft.error().message;
    EXPECT_GT(stiff->sag.tip_drop_mm, 0.0) << "a chrysanthemum's head pulls its top below its base";
    EXPECT_GT(soft->sag.tip_drop_mm, stiff->sag.tip_drop_mm + 20.0);
    EXPECT_GT(soft->sag.tip_angle_deg, stiff->sag.tip_angle_deg);
    EXPECT_GE(soft->stands[1].tilt_deg, stiff->stands[1].tilt_deg);
}

TEST(SpeciesMechanics, ABrokenFileIsNamedAndNoTrialRuns) {
    const auto dir = std::filesystem::temp_directory_path() / "ikebana-mechanics-broken";
    std::filesystem::create_directories(dir);
    ASSERT_TRUE(assets::write_text_file(dir / "broken.json", "{\"format\": \"ikebana-species/1\"}"));
    const auto m = species_mechanics(dir / "broken.json");
    ASSERT_FALSE(m);
    EXPECT_NE(m.error().message.find("broken.json"), std::string::npos) << m.error().message;
}
