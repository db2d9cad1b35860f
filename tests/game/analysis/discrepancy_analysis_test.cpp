#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "engine/assets/csv_table.hpp"
#include "game/analysis/discrepancy_analysis.hpp"
#include "game/analysis/measured_data.hpp"
#include "game/analysis/svg_plot.hpp"
#include "game/analysis/term_shapes.hpp"
#include "systems/insertion/deterioration.hpp"

using namespace ikebana;
using namespace ikebana::game;

namespace {

CovariateColumn numeric_column(const std::string& name, std::vector<double> values) {
    CovariateColumn c;
    c.name = name;
    c.values = std::move(values);
    return c;
}

// Rows of `flowers` flowers x `per_flower` trials; predicted 100 gf; measured = 100 * exp(effect + noise).
AnalysisInput small_input(std::size_t flowers, std::size_t per_flower, double slope, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> noise(0.0, 0.03);
    AnalysisInput in;
    std::vector<double> x, z;
    for (std::size_t f = 0; f < flowers; ++f) {
        for (std::size_t k = 0; k < per_flower; ++k) {
            const double xv = static_cast<double>(k + 1);
            in.flower.push_back("f" + std::to_string(f));
            in.predicted_gf.push_back(100.0);
            in.measured_gf.push_back(100.0 * std::exp(slope * xv + noise(rng)));
            x.push_back(xv);
            z.push_back(noise(rng));
        }
    }
    in.covariates.columns.push_back(numeric_column("count", x));
    in.covariates.columns.push_back(numeric_column("unrelated", z));
    return in;
}

} // namespace

TEST(TermShapes, AFittedTermMeansTheSameInTheSpeciesModel) {
    const auto column = numeric_column("soak", {0.0, 3.0, 7.5, 12.0, 30.0, 45.0, 90.0});
    for (const auto& shape : all_shapes_of(column)) {
        const Eigen::MatrixXd basis = basis_of(column, shape);
        // A coefficient of the size a fit gives: at most 0.5 in the exponent over the data.
        const double coefficient = 0.5 / std::max(basis.cwiseAbs().maxCoeff(), 1e-9);
        const auto terms = terms_of(column, shape, Eigen::VectorXd::Constant(1, coefficient));
        ASSERT_EQ(terms.size(), 1u);
        for (std::size_t i = 0; i < column.values.size(); ++i) {
            systems::insertion::Covariates cov;
            cov.numeric["soak"] = column.values[i];
            EXPECT_NEAR(systems::insertion::extension_factor(terms, 1, cov), std::exp(coefficient * basis(static_cast<Eigen::Index>(i), 0)), 1e-12)
                << shape.form << " at " << column.values[i];
        }
        // Beyond a tenth of the fitted range the curve holds its value instead of extrapolating.
        systems::insertion::Covariates far, edge;
        far.numeric["soak"] = 1000.0;
        edge.numeric["soak"] = 99.0;
        EXPECT_DOUBLE_EQ(systems::insertion::extension_factor(terms, 1, far), systems::insertion::extension_factor(terms, 1, edge)) << shape.form;
    }
}

// A term at coefficient 1 can sum far beyond the factor's +-5 clamp (a square over 1..6 reaches 36):
// the holding fit reads each term's own basis from extension_exponent, which does not clamp, while the
// physics' factor stays within e^-5..e^5. Read through the clamp, the fit once promised log-loss 0.36
// for a holding whose species, run, gave 1.15.
TEST(TermShapes, ATermsOwnSumIsNotClampedWhereThePhysicsFactorIs) {
    components::DeteriorationTerm square{};
    square.covariate = "insertion";
    square.form = "power";
    square.scale = 2.0;
    square.origin = -2.0;
    square.coefficient = 1.0;
    const systems::insertion::Covariates none;
    EXPECT_NEAR(systems::insertion::extension_exponent({square}, 4, none), 36.0, 1e-9);
    EXPECT_NEAR(systems::insertion::extension_factor({square}, 4, none), std::exp(5.0), 1e-9);
    square.coefficient = 0.02;
    EXPECT_NEAR(std::log(systems::insertion::extension_factor({square}, 4, none)), systems::insertion::extension_exponent({square}, 4, none), 1e-12);
}

// Issue 17: a term on a column the world does not set once dropped out, leaving the fitted level alone
// (18 gf a pin for a species fitted at 100: every flower fell). It is taken at the centre of the
// range it was fitted on, and missing_covariates says so; a category falls back to its reference level.
TEST(TermShapes, ATermOnAColumnTheWorldDoesNotSetIsTakenAtItsFittedRangesCentre) {
    const std::vector<components::DeteriorationTerm> terms = {
        {"level", "constant", -1.2, 0.0, "", 0.0, 0.0, 0.0, "", 0.0, 0.0, 0.0},
        {"stem_water_content", "linear", 1.5, 0.0, "", 0.0, 0.6, 0.9, "", 0.0, 0.0, 0.0},
        {"vase", "category", 0.2, 0.0, "metal", 0.0, 0.0, 0.0, "", 0.0, 0.0, 0.0},
        {"angle_deg", "linear", 0.01, 0.0, "", 0.0, 10.0, 90.0, "", 0.0, 0.0, 0.0}, // set by the insertion itself
    };
    systems::insertion::Covariates none, centre;
    none.numeric["angle_deg"] = 45.0;
    centre.numeric["angle_deg"] = 45.0;
    centre.numeric["stem_water_content"] = 0.75;
    EXPECT_DOUBLE_EQ(systems::insertion::extension_factor(terms, 1, none), systems::insertion::extension_factor(terms, 1, centre));
    EXPECT_NEAR(systems::insertion::extension_factor(terms, 1, none), std::exp(-1.2 + 1.5 * 0.75 + 0.45), 1e-12);
    const auto missing = systems::insertion::missing_covariates(terms, {});
    ASSERT_EQ(missing.size(), 2u) << "angle_deg is the insertion's own";
    EXPECT_EQ(missing[0].name, "stem_water_content");
    EXPECT_TRUE(missing[0].numeric);
    EXPECT_DOUBLE_EQ(missing[0].value, 0.75);
    EXPECT_EQ(missing[1].name, "vase");
    EXPECT_FALSE(missing[1].numeric);
    systems::insertion::Covariates given;
    given.numeric["stem_water_content"] = 0.62;
    given.category["vase"] = "glass";
    EXPECT_TRUE(systems::insertion::missing_covariates(terms, given).empty());
}

TEST(TermShapes, AWildTermCannotGiveTheSimulationAnInfiniteFactor) {
    const std::vector<components::DeteriorationTerm> wild = {
        {"x", "power", 50.0, 3.0, "", 0.0, 0.0, 0.0, "", 0.0, 0.0, 0.0}, {"y", "log", 1.0, 0.0, "", 0.0, 0.0, 0.0, "", 0.0, 0.0, 0.0}};
    systems::insertion::Covariates cov;
    cov.numeric["x"] = 1e6;
    cov.numeric["y"] = -5.0; // log of a negative: the basis guards it
    const double f = systems::insertion::extension_factor(wild, 1, cov);
    EXPECT_TRUE(std::isfinite(f));
    EXPECT_LE(f, std::exp(5.0));
}

TEST(TermShapes, CategoriesAreFactorsAgainstTheMostCommonLevel) {
    CovariateColumn c;
    c.name = "vase";
    c.numeric = false;
    c.levels = {"glass", "metal", "ceramic"};
    c.level = {0, 1, 2, 0};
    const auto terms = terms_of(c, {"category", 0.0, 0.0}, Eigen::Vector2d(-0.2, 0.1));
    ASSERT_EQ(terms.size(), 2u);
    systems::insertion::Covariates metal, glass;
    metal.category["vase"] = "metal";
    glass.category["vase"] = "glass";
    EXPECT_NEAR(systems::insertion::extension_factor(terms, 1, metal), std::exp(-0.2), 1e-12);
    EXPECT_DOUBLE_EQ(systems::insertion::extension_factor(terms, 1, glass), 1.0);
}

TEST(DiscrepancyAnalysis, RefusesNonPositiveForcesNamingTheRow) {
    auto in = small_input(6, 4, 0.0, 1);
    in.measured_gf[5] = 0.0;
    const auto result = analyse_discrepancy(in, {});
    ASSERT_FALSE(result);
    EXPECT_NE(result.error().message.find("row 6"), std::string::npos) << result.error().message;
}

TEST(DiscrepancyAnalysis, FindsATrendAndLeavesTheUnrelatedColumnAlone) {
    const auto result = analyse_discrepancy(small_input(12, 6, -0.05, 3), {});
    ASSERT_TRUE(result) << result.error().message;
    ASSERT_EQ(result->causes.size(), 1u);
    EXPECT_EQ(result->causes[0].covariate, "count");
    EXPECT_EQ(result->causes[0].direction, "decreases");
    // exp(-0.05 * (5.75 - 1.25)) - 1 = -0.20 across the 5th-95th percentiles.
    EXPECT_NEAR(result->causes[0].effect_size, -0.20, 0.04);
    EXPECT_LT(result->causes[0].effect_low, result->causes[0].effect_size);
    EXPECT_GT(result->causes[0].effect_high, result->causes[0].effect_size);
    EXPECT_GT(result->gain, 0.3);
    EXPECT_FALSE(result->rows_as_groups);
    EXPECT_LT(result->extended_cv_rmse_gf, result->baseline_cv_rmse_gf);
}

// A rare level (three flowers of 60) with a real effect: a flower resample that misses it knows
// nothing of the level and must not count as "no effect" (5 % of resamples did, and the interval
// reached to 0).
TEST(DiscrepancyAnalysis, ARareLevelsIntervalIsNotPulledToZeroByResamplesWithoutIt) {
    AnalysisInput in;
    CovariateColumn vase;
    vase.name = "vase";
    vase.numeric = false;
    vase.levels = {"glass", "metal"};
    std::mt19937_64 rng(4);
    std::normal_distribution<double> noise(0.0, 0.03);
    for (int f = 0; f < 60; ++f) {
        for (int k = 0; k < 6; ++k) {
            const bool metal = f < 3;
            in.flower.push_back("F" + std::to_string(f));
            in.predicted_gf.push_back(300.0);
            in.measured_gf.push_back(300.0 * std::exp((metal ? -0.2 : 0.0) + noise(rng)));
            vase.level.push_back(metal ? 1u : 0u);
        }
    }
    in.covariates.columns.push_back(vase);
    AnalysisOptions o;
    o.bootstrap = 200;
    const auto result = analyse_discrepancy(in, o);
    ASSERT_TRUE(result) << result.error().message;
    ASSERT_FALSE(result->causes.empty());
    EXPECT_EQ(result->causes[0].category, "metal");
    EXPECT_LT(result->causes[0].effect_high, -0.12) << "[" << result->causes[0].effect_low << ", " << result->causes[0].effect_high << "]";
    EXPECT_GT(result->causes[0].effect_low, -0.25);
}

TEST(DiscrepancyAnalysis, NoEffectGivesNoCausesAndNoGain) {
    const auto result = analyse_discrepancy(small_input(12, 6, 0.0, 4), {});
    ASSERT_TRUE(result) << result.error().message;
    EXPECT_FALSE(result->discrepancy_found);
    EXPECT_TRUE(result->causes.empty());
    EXPECT_TRUE(result->extension.empty());
    EXPECT_EQ(result->gain, 0.0);
    EXPECT_EQ(result->extended_cv_rmse_gf, result->baseline_cv_rmse_gf);
}

TEST(DiscrepancyAnalysis, FewerThanFourFlowersLetRowsStandInForThem) {
    const auto result = analyse_discrepancy(small_input(1, 12, -0.04, 5), {});
    ASSERT_TRUE(result) << result.error().message;
    EXPECT_TRUE(result->rows_as_groups);
    EXPECT_EQ(result->n_flowers, 1u);
    ASSERT_FALSE(result->causes.empty());
    EXPECT_EQ(result->causes[0].covariate, "count");
}

TEST(DiscrepancyAnalysis, SameSeedSameAnswer) {
    const auto in = small_input(10, 5, -0.03, 6);
    const auto a = analyse_discrepancy(in, {});
    const auto b = analyse_discrepancy(in, {});
    ASSERT_TRUE(a && b);
    EXPECT_EQ(a->diagnostics[0].p_value, b->diagnostics[0].p_value);
    EXPECT_EQ(a->extended_cv_rmse_gf, b->extended_cv_rmse_gf);
}

TEST(SvgPlot, DrawsEveryPointAndEscapesText) {
    SvgChart chart;
    chart.title = "force <gf> & more";
    chart.series.push_back({"rows", "#000", {1, 2, 3}, {10, 20, 40}, {}, {}, false, 2.0, 1.0, "circle", {}});
    chart.log_y = true;
    const std::string svg = render_svg(chart);
    const std::string plot = svg.substr(svg.find("<g>"), svg.find("</g>") - svg.find("<g>")); // the points, not the legend
    std::size_t circles = 0;
    for (std::size_t at = plot.find("<circle"); at != std::string::npos; at = plot.find("<circle", at + 1)) ++circles;
    EXPECT_EQ(circles, 3u);
    EXPECT_NE(svg.find("force &lt;gf&gt; &amp; more"), std::string::npos);
    EXPECT_EQ(svg.find("nan"), std::string::npos);
}

// Issue 17's report: two series that fall on each other are told apart by their markers, each point
// can say which insertion it is, and a narrow log axis has round ticks (not 1.828 and 0.9259).
TEST(SvgPlot, OverlappingSeriesHaveTheirOwnMarkersAndNarrowAxesRoundTicks) {
    SvgChart chart;
    chart.log_y = true;
    chart.series.push_back({"fit", "#1f77b4", {1, 2}, {0.9259, 1.828}, {}, {}, false, 3.0, 1.0, "square", {"1", "2"}});
    chart.series.push_back({"simulated", "#2ca02c", {1, 2}, {0.9259, 1.828}, {}, {}, false, 3.0, 1.0, "triangle", {}});
    const std::string svg = render_svg(chart);
    const std::string plot = svg.substr(svg.find("<g>"), svg.find("</g>") - svg.find("<g>"));
    std::size_t squares = 0, triangles = 0;
    for (std::size_t at = plot.find("<rect"); at != std::string::npos; at = plot.find("<rect", at + 1)) ++squares;
    for (std::size_t at = plot.find("<polygon"); at != std::string::npos; at = plot.find("<polygon", at + 1)) ++triangles;
    EXPECT_EQ(squares, 2u);
    EXPECT_EQ(triangles, 2u);
    EXPECT_NE(plot.find(">1</text>"), std::string::npos) << "the point's label";
    EXPECT_NE(svg.find(">1.25</text>"), std::string::npos) << svg;
    EXPECT_NE(svg.find(">1.5</text>"), std::string::npos);
    EXPECT_EQ(svg.find(">1.828</text>"), std::string::npos);
    EXPECT_EQ(svg.find(">0.9259</text>"), std::string::npos);
}

// Mutated measured files: every one either reads, and then analyses to finite figures, or is refused
// with the file's name; nothing crashes and nothing comes back half read.
TEST(DiscrepancyAnalysis, MutatedFilesAreReadAndAnalysedOrRefusedNeverCrash) {
    const std::string valid =
        "flower_id,insertion,max_force_gf,angle_deg,room,temp\n"
        "A,1,480,45,dry,21.5\nA,2,450,45,dry,21.7\nA,3,410,45,dry,22.0\nB,1,470,30,humid,19.0\n"
        "B,2,445,30,humid,19.4\nB,3,400,30,humid,19.9\nC,1,490,60,dry,23.1\nC,2,460,60,dry,23.0\n"
        "C,3,420,60,dry,23.4\nD,1,475,45,humid,20.2\nD,2,440,45,humid,20.5\nD,3,405,45,humid,20.9\n";
    const std::string alphabet = ",\n\"#-.e0123456789abcAB \t";
    std::mt19937_64 rng(7);
    AnalysisOptions options;
    options.permutations = 49;
    options.bootstrap = 10;
    std::size_t analysed = 0;
    for (int round = 0; round < 300; ++round) {
        std::string text = valid;
        const int edits = 1 + static_cast<int>(rng() % 4);
        for (int e = 0; e < edits; ++e) {
            const std::size_t at = rng() % text.size();
            switch (rng() % 3) {
            case 0: text[at] = alphabet[rng() % alphabet.size()]; break;
            case 1: text.erase(at, 1 + rng() % 3); break;
            default: text.insert(at, 1, alphabet[rng() % alphabet.size()]); break;
            }
        }
        auto table = assets::parse_csv(text, "mutated.csv");
        if (!table) {
            EXPECT_NE(table.error().message.find("mutated.csv"), std::string::npos) << table.error().message;
            continue;
        }
        auto data = read_measured_data(std::move(table).value());
        if (!data) {
            EXPECT_NE(data.error().message.find("mutated.csv"), std::string::npos) << data.error().message;
            continue;
        }
        auto covariates = candidate_covariates(data->table, {});
        ASSERT_TRUE(covariates);
        AnalysisInput in;
        for (const auto& t : data->trials) {
            in.flower.push_back(t.flower_id);
            in.measured_gf.push_back(t.max_force_gf);
            in.predicted_gf.push_back(400.0 + 10.0 * t.insertion);
        }
        in.covariates = std::move(covariates).value();
        const auto result = analyse_discrepancy(in, options);
        if (!result) continue; // too few rows: refused with a reason
        ++analysed;
        EXPECT_TRUE(std::isfinite(result->baseline_rmse_gf));
        EXPECT_TRUE(std::isfinite(result->extended_cv_rmse_gf));
        EXPECT_TRUE(std::isfinite(result->gain));
    }
    EXPECT_GT(analysed, 30u) << "most mutations still read";
}
