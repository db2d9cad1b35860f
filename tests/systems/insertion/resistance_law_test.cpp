#include <gtest/gtest.h>

#include "systems/insertion/deterioration.hpp"
#include "systems/insertion/pin_geometry.hpp"
#include "systems/insertion/resistance_law.hpp"

using namespace ikebana;
using namespace ikebana::components;
using namespace ikebana::systems::insertion;

namespace {
constexpr double gf = 9.80665e-3;
constexpr double gf_per_mm = gf / 1e-3;

PinResistance table1() {
    PinResistance m{};
    m.kind = ResistanceKind::hard_eq6;
    m.cortex_tip_n_per_m = 711 * gf_per_mm;
    m.cortex_trunk_n_per_m = 316 * gf_per_mm;
    m.pith_tip_n_per_m = 40 * gf_per_mm;
    m.pith_trunk_n_per_m = 7 * gf_per_mm;
    m.pith_diameter_m = 0.003;
    return m;
}

// A horizontal hard branch (radius 4 mm, pith radius 1.5 mm) with its axis at height `axis_mm`,
// directly above one pin (base at 0, trunk to 11.5 mm, tip to 13 mm): Eq. 6 in gf.
double eq6_gf(double axis_mm) {
    const StemEnd stem{{-0.02, 0.0, axis_mm * 1e-3}, {1, 0, 0}, 0.004, 0.0015, 0.0, 0.05};
    const auto contact = pin_contact(stem, {0, 0, 0}, PinShape{0.0009, 0.0115, 0.0015});
    EXPECT_TRUE(contact);
    return contact ? pin_resistance_n(*contact, table1(), 0.0) / gf : 0.0;
}
} // namespace

// Figure 11's four types, by where the pin's tip ends. Hand computation (lengths in mm):
TEST(ResistanceLaw, Eq6TipInFirstCortex) {
    // Stem 11..19, pith 13.5..16.5: tip 11.5..13 all in cortex, trunk 11..11.5 in cortex.
    EXPECT_NEAR(eq6_gf(15.0), 711 * 1.5 + 316 * 0.5, 1e-6);
}
TEST(ResistanceLaw, Eq6TipInPith) {
    // Stem 9.5..17.5, pith 12..15: tip 0.5 in cortex + 1.0 in pith, trunk 9.5..11.5 in cortex.
    EXPECT_NEAR(eq6_gf(13.5), 711 * 0.5 + 40 * 1.0 + 316 * 2.0, 1e-6);
}
TEST(ResistanceLaw, Eq6TipInSecondCortex) {
    // Stem 6.5..14.5, pith 9..12: trunk 6.5..9 cortex, 9..11.5 pith; tip 11.5..12 pith, 12..13 cortex.
    EXPECT_NEAR(eq6_gf(10.5), 711 * 1.0 + 40 * 0.5 + 316 * 2.5 + 7 * 2.5, 1e-6);
}
TEST(ResistanceLaw, Eq6PinThroughTheStem) {
    // Stem 2..10, pith 4.5..7.5: the trunk crosses cortex (2 + 3 mm) and pith (3 mm); the tip is out.
    EXPECT_NEAR(eq6_gf(6.0), 316 * 5.0 + 7 * 3.0, 1e-6);
}

// The paper's baseline: Table 2 for insertions 1 and 2, the mean of 3..6 from the third on.
TEST(ResistanceLaw, PaperBaselineReproducesTable2) {
    const std::vector<double> table2 = {9.3, 8.8, 7.9, 7.7, 7.5, 7.4};
    const auto baseline = expand_deterioration("paper_baseline", table2);
    ASSERT_EQ(baseline.size(), 3u);
    EXPECT_DOUBLE_EQ(baseline[0], 9.3);
    EXPECT_DOUBLE_EQ(baseline[1], 8.8);
    EXPECT_NEAR(baseline[2], 7.625, 1e-12) << "printed as 7.6 in Table 2";
    PinResistance m{};
    m.kind = ResistanceKind::soft_table;
    for (double v : baseline) m.n_per_m_by_insertion.push_back(v * gf_per_mm);
    // A pin fully in the stem (13 mm) gives Table 2's maximum for one pin, within rounding.
    const PinContact full{0, 0.0015, 0.0115, 0, 0, 0, 0};
    const double expected_gf[] = {121, 115, 100, 100, 100, 100, 100, 100};
    for (std::uint32_t n = 1; n <= 8; ++n) {
        EXPECT_NEAR(pin_resistance_n(full, m, soft_resistance_n_per_m(m, n)) / gf, expected_gf[n - 1], 1.0) << "insertion " << n;
    }
}

TEST(ResistanceLaw, OtherDeteriorationModels) {
    const std::vector<double> t = {9.3, 8.8, 7.9};
    EXPECT_EQ(expand_deterioration("table_hold_last", t), t);
    EXPECT_EQ(expand_deterioration("none", t), std::vector<double>{9.3});
    EXPECT_TRUE(expand_deterioration("unknown", t).empty());
}

TEST(ResistanceLaw, ExtensionTermsMultiplyTheBaseline) {
    PinResistance m{};
    m.n_per_m_by_insertion = {100.0};
    m.extension = {{"insertion", "log", -0.1, 0.0, "", 0.0, 0.0, 0.0, "", 0.0, 0.0, 0.0}, {"room", "category", 0.2, 0.0, "humid", 0.0, 0.0, 0.0, "", 0.0, 0.0, 0.0}};
    Covariates c;
    c.category["room"] = "humid";
    EXPECT_NEAR(soft_resistance_n_per_m(m, 4, c), 100.0 * std::exp(-0.1 * std::log(4.0) + 0.2), 1e-9);
    c.category["room"] = "dry";
    EXPECT_NEAR(soft_resistance_n_per_m(m, 1, c), 100.0, 1e-9);
}
