#include <gtest/gtest.h>

#include <filesystem>
#include <random>

#include "engine/assets/files.hpp"
#include "engine/assets/csv_table.hpp"
#include "engine/assets/json_checker.hpp"
#include "game/species/species.hpp"

using namespace ikebana;
using namespace ikebana::game;

namespace {
std::string sunflower_text() {
    return *assets::read_text_file(std::string(IKEBANA_ASSET_DIR) + "/species/sunflower.json");
}
std::string replace(std::string text, const std::string& from, const std::string& to) {
    const auto at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return text.replace(at, from.size(), to);
}
} // namespace

TEST(Species, ShippedFilesLoad) {
    for (const auto& entry : std::filesystem::directory_iterator(std::string(IKEBANA_ASSET_DIR) + "/species")) {
        const auto sp = load_species_file(entry.path());
        EXPECT_TRUE(sp) << entry.path() << ": " << (sp ? "" : sp.error().message);
    }
}

TEST(Species, SunflowerIsThePapersFlowerInSI) {
    const auto sp = load_species("sunflower");
    ASSERT_TRUE(sp);
    EXPECT_DOUBLE_EQ(sp->length_m, 0.230);
    EXPECT_DOUBLE_EQ(sp->diameter_m, 0.0075);
    ASSERT_TRUE(sp->soft.has_value());
    ASSERT_EQ(sp->soft->n_per_m_by_insertion.size(), 6u);
    EXPECT_NEAR(sp->soft->n_per_m_by_insertion[0], 9.3 * 9.80665, 1e-9) << "9.3 gf/mm in N/m";
    EXPECT_NEAR(sp->soft->max_per_pin_n_by_insertion[0], 121 * 9.80665e-3, 1e-12);
    EXPECT_EQ(sp->deterioration.model, "paper_baseline");
}

TEST(Species, WrongTypeIsReportedWithFileAndPath) {
    const auto sp = parse_species(replace(sunflower_text(), "\"segments\": 20", "\"segments\": \"ten\""), "sunflower.json");
    ASSERT_FALSE(sp);
    EXPECT_EQ(sp.error().message, "sunflower.json: /stem/segments: expected an integer >= 2 and <= 200, got \"ten\"");
}

TEST(Species, EveryProblemIsReportedNotJustTheFirst) {
    auto text = replace(sunflower_text(), "\"segments\": 20", "\"segments\": 1");
    text = replace(text, "\"diameter_mm\": 7.5", "\"diameter_mm\": -7.5");
    text = replace(text, "\"collision\": \"inactive\"", "\"collision\": \"sometimes\"");
    text = replace(text, "\"mass_g\": 8", "\"mas_g\": 8");
    const auto sp = parse_species(text, "s.json");
    ASSERT_FALSE(sp);
    const auto& m = sp.error().message;
    EXPECT_NE(m.find("s.json: /stem/segments: expected an integer >= 2"), std::string::npos) << m;
    EXPECT_NE(m.find("s.json: /stem/diameter_mm: expected a number in [0.5, 100], got -7.5"), std::string::npos) << m;
    EXPECT_NE(m.find("s.json: /parts/0/collision: expected one of \"active\", \"passive\", \"inactive\""), std::string::npos) << m;
    EXPECT_NE(m.find("s.json: /stem/mas_g: unknown field"), std::string::npos) << m;
    EXPECT_NE(m.find("s.json: /stem/mass_g: missing"), std::string::npos) << m;
}

TEST(Species, SyntaxErrorNamesLineAndColumn) {
    const auto sp = parse_species("{\n  \"format\": \"ikebana-species/1\",\n  \"id\": sunflower\n}", "bad.json");
    ASSERT_FALSE(sp);
    EXPECT_EQ(sp.error().message.rfind("bad.json:3:", 0), 0u) << sp.error().message;
}

TEST(Species, ResistanceModelMustMatchBranchKind) {
    const auto sp = parse_species(replace(sunflower_text(), "\"branch\": \"soft\"", "\"branch\": \"hard\""), "s.json");
    ASSERT_FALSE(sp);
    EXPECT_NE(sp.error().message.find("/resistance/model"), std::string::npos);
}

TEST(Species, MissingFileIsNotFound) {
    const auto sp = load_species("does_not_exist");
    ASSERT_FALSE(sp);
    EXPECT_EQ(sp.error().code, ErrorCode::not_found);
    EXPECT_NE(sp.error().message.find("does_not_exist.json"), std::string::npos);
}

// Property: whatever the bytes, the loader answers with a species whose numbers are in range, or an
// error that names the file; it never crashes and never returns half a species.
TEST(Species, MutatedFilesNeverCrashTheLoader) {
    const std::string original = sunflower_text();
    std::mt19937_64 rng(2024);
    const std::string alphabet = "{}[]\":,.-+eE0123456789 \n\tabcnulltruefalse\\";
    std::size_t accepted = 0;
    for (int iteration = 0; iteration < 3000; ++iteration) {
        std::string text = original;
        const int edits = 1 + static_cast<int>(rng() % 4);
        for (int k = 0; k < edits && !text.empty(); ++k) {
            const std::size_t at = rng() % text.size();
            switch (rng() % 5) {
            case 0: text.erase(at, 1 + rng() % 8); break;
            case 1: text.insert(at, 1, alphabet[rng() % alphabet.size()]); break;
            case 2: text[at] = alphabet[rng() % alphabet.size()]; break;
            case 3: text.resize(at); break;
            default: text.insert(at, text.substr(rng() % text.size(), 1 + rng() % 16)); break;
            }
        }
        const auto sp = parse_species(text, "fuzz.json");
        if (sp) {
            ++accepted;
            EXPECT_GE(sp->segments, 2u);
            EXPECT_GT(sp->length_m, 0.0);
            EXPECT_GT(sp->diameter_m, 0.0);
            EXPECT_GT(sp->youngs_modulus_pa, 0.0);
            EXPECT_TRUE(sp->soft.has_value() || sp->hard.has_value());
        } else {
            EXPECT_EQ(sp.error().message.rfind("fuzz.json", 0), 0u) << sp.error().message;
        }
    }
    EXPECT_GT(accepted, 0u) << "some mutations (inside strings, whitespace) are harmless";
}

// Property at the JSON level: any field replaced by a value of another type is reported at its path.
TEST(Species, AnyFieldWithWrongTypeIsReportedAtItsPath) {
    const auto root = assets::Json::parse(sunflower_text());
    const std::vector<assets::Json> wrong = {"text", -1, nullptr, assets::Json::array(), assets::Json::object(), true};
    std::size_t reported = 0;
    std::size_t tried = 0;
    const auto flat = root.flatten(); // keep it alive: items() refers into it
    for (const auto& [pointer, value] : flat.items()) {
        if (pointer == "/notes" || pointer == "/name") continue; // free text: any string is fine
        for (const auto& w : wrong) {
            auto mutated = root;
            mutated[assets::Json::json_pointer(pointer)] = w;
            const auto sp = parse_species(mutated.dump(), "m.json");
            ++tried;
            if (!sp) {
                ++reported;
                EXPECT_NE(sp.error().message.find("m.json: /"), std::string::npos);
            }
        }
    }
    // A few replacements are legitimately accepted (e.g. a mesh path given as another string).
    EXPECT_GT(static_cast<double>(reported), 0.9 * static_cast<double>(tried));
}

// The paper's Table 2 ships twice: as data to validate against and inside the sunflower species.
// They must agree.
TEST(Species, SunflowerCarriesThePapersTable2) {
    const auto table = assets::load_csv(std::string(IKEBANA_ASSET_DIR) + "/data/paper/table2_sunflower.csv");
    ASSERT_TRUE(table) << table.error().message;
    const auto sp = load_species("sunflower");
    ASSERT_TRUE(sp && sp->soft);
    const auto& per_mm = *table->find("resistance_gf_per_mm")->numbers;
    const auto& per_pin = *table->find("max_per_pin_gf")->numbers;
    ASSERT_EQ(per_mm.size(), sp->soft->n_per_m_by_insertion.size());
    for (std::size_t i = 0; i < per_mm.size(); ++i) {
        EXPECT_NEAR(sp->soft->n_per_m_by_insertion[i], per_mm[i] * gram_force_n / 1e-3, 1e-9);
        EXPECT_NEAR(sp->soft->max_per_pin_n_by_insertion[i], per_pin[i] * gram_force_n, 1e-12);
    }
}

// Twisting: G J from E and Poisson's ratio (0.3 when not given), or a measured shear modulus; a ratio
// no material has is refused with its path.
TEST(Species, TwistStiffnessComesFromPoissonsRatioOrAShearModulus) {
    const auto plain = parse_species(sunflower_text(), "sunflower.json");
    ASSERT_TRUE(plain) << plain.error().message;
    EXPECT_DOUBLE_EQ(plain->poisson_ratio, 0.3);
    EXPECT_EQ(plain->shear_modulus_pa, 0.0);
    const auto given = parse_species(replace(sunflower_text(), "\"segments\": 20", "\"segments\": 20, \"poisson_ratio\": 0.4, \"shear_modulus_mpa\": 90"), "sunflower.json");
    ASSERT_TRUE(given) << given.error().message;
    EXPECT_DOUBLE_EQ(given->poisson_ratio, 0.4);
    EXPECT_DOUBLE_EQ(given->shear_modulus_pa, 90e6);
    const auto wrong = parse_species(replace(sunflower_text(), "\"segments\": 20", "\"segments\": 20, \"poisson_ratio\": 0.7"), "sunflower.json");
    ASSERT_FALSE(wrong);
    EXPECT_NE(wrong.error().message.find("sunflower.json: /stem/poisson_ratio: "), std::string::npos) << wrong.error().message;
}

// A part without a mesh is drawn as a shape, each field with a default from its kind; a width wider
// than the part is long, or shape fields beside a mesh they would not apply to, are refused by path.
TEST(Species, APartWithoutAMeshHasAShapeAndItsFieldsAreChecked) {
    const auto iris = load_species("iris");
    ASSERT_TRUE(iris) << iris.error().message;
    ASSERT_GE(iris->parts.size(), 1u);
    EXPECT_EQ(iris->parts[0].mesh, "");
    EXPECT_EQ(iris->parts[0].shape.outline, PartOutline::sword);
    EXPECT_NEAR(iris->parts[0].shape.width, 16.0 / 280.0, 1e-12);
    EXPECT_NEAR(iris->parts[0].shape.fold_rad, 22.0 * M_PI / 180.0, 1e-12);
    EXPECT_NEAR(iris->parts[1].shape.fold_rad, 20.0 * M_PI / 180.0, 1e-12) << "a sword leaf's default fold";
    EXPECT_TRUE(iris->parts[2].shape.round_tip);

    const std::string leaf = "{ \"kind\": \"leaf\", \"mesh\": \"meshes/leaf.gltf\", \"count\": 2, \"at\": 0.6, \"size_mm\": 70, \"collision\": \"passive\" }";
    const auto plain = parse_species(replace(sunflower_text(), leaf, "{ \"kind\": \"leaf\", \"count\": 2, \"at\": 0.6, \"size_mm\": 70, \"collision\": \"passive\" }"), "sunflower.json");
    ASSERT_TRUE(plain) << plain.error().message;
    EXPECT_EQ(plain->parts[1].shape.outline, PartOutline::leaf);
    EXPECT_NEAR(plain->parts[1].shape.width, 0.44, 1e-12);
    EXPECT_FALSE(plain->parts[1].shape.round_tip);

    const auto wide = parse_species(replace(sunflower_text(), leaf, "{ \"kind\": \"leaf\", \"count\": 2, \"at\": 0.6, \"size_mm\": 70, \"width_mm\": 80, \"collision\": \"passive\" }"), "sunflower.json");
    ASSERT_FALSE(wide);
    EXPECT_EQ(wide.error().message, "sunflower.json: /parts/1/width_mm: expected at most the part's size_mm (70): a part is measured along its length, got 80");
    const auto both = parse_species(replace(sunflower_text(), leaf, "{ \"kind\": \"leaf\", \"mesh\": \"meshes/leaf.gltf\", \"shape\": \"sword\", \"count\": 2, \"at\": 0.6, \"size_mm\": 70, \"collision\": \"passive\" }"), "sunflower.json");
    ASSERT_FALSE(both);
    EXPECT_EQ(both.error().message, "sunflower.json: /parts/1/shape: describes the shape drawn without a mesh, and this part names one (/mesh): give one or the other");
    const auto oval = parse_species(replace(sunflower_text(), leaf, "{ \"kind\": \"leaf\", \"shape\": \"oval\", \"count\": 2, \"at\": 0.6, \"size_mm\": 70, \"collision\": \"passive\" }"), "sunflower.json");
    ASSERT_FALSE(oval);
    EXPECT_NE(oval.error().message.find("sunflower.json: /parts/1/shape: "), std::string::npos) << oval.error().message;
}

// Issue 57: a deterioration term with "applies_to": "hold" is a term on what holds a stem at rest alone;
// the others stay the push's (and the holding's, as the block says). Any other value is named at its path.
TEST(Species, ATermOnTheHoldingAloneIsReadApartFromThePushTerms) {
    const std::string extended = R"("deterioration": {"model": "extended", "base": "paper_baseline", "terms": [
        {"covariate": "insertion", "form": "log", "coefficient": -0.08, "scale": 0},
        {"covariate": "insertion", "form": "constant", "coefficient": -0.04, "applies_to": "hold"}]})";
    const std::string text = sunflower_text();
    const auto from = text.find("\"deterioration\"");
    ASSERT_NE(from, std::string::npos);
    const auto to = text.find('}', from);
    const std::string with_hold = text.substr(0, from) + extended + text.substr(to + 1);
    const auto sp = parse_species(with_hold, "held.json");
    ASSERT_TRUE(sp) << sp.error().message;
    ASSERT_EQ(sp->deterioration.terms.size(), 1u);
    EXPECT_EQ(sp->deterioration.terms[0].form, "log");
    ASSERT_EQ(sp->deterioration.hold_terms.size(), 1u);
    EXPECT_DOUBLE_EQ(sp->deterioration.hold_terms[0].coefficient, -0.04);
    const auto bad = parse_species(replace(with_hold, "\"applies_to\": \"hold\"", "\"applies_to\": \"stand\""), "held.json");
    ASSERT_FALSE(bad);
    EXPECT_NE(bad.error().message.find("held.json: /deterioration/terms/1/applies_to: expected one of"), std::string::npos) << bad.error().message;
}
