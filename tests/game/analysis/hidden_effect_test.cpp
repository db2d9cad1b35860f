// The analysis must find an effect hidden in synthetic data through the data alone: the generator's
// column names appear here only to score the answer, never in the analysis.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "synthetic_trials.hpp"
#include "systems/insertion/deterioration.hpp"

using namespace ikebana;
using namespace ikebana::game;
using namespace ikebana::test;

namespace {

constexpr std::uint32_t seeds = 40;

InsertionPredictor& shared_predictor() {
    static InsertionPredictor predictor;
    return predictor;
}

AnalysisOptions options_for(std::uint64_t seed) {
    AnalysisOptions o;
    o.seed = seed;
    o.permutations = 1000;
    o.bootstrap = 100;
    return o;
}

// RMSE in gf on held-out rows of the simulation times a factor per row.
double held_out_rmse(const SyntheticData& d, const std::vector<double>& log_factor) {
    double s = 0.0;
    for (std::size_t i = 0; i < d.data.trials.size(); ++i) {
        const double e = d.data.trials[i].max_force_gf - d.simulated_gf[i] * std::exp(log_factor[i]);
        s += e * e;
    }
    return std::sqrt(s / static_cast<double>(d.data.trials.size()));
}

class HiddenEffect : public ::testing::TestWithParam<PlantedEffect> {};

} // namespace

TEST_P(HiddenEffect, PlantedCauseIsNamedFirstAndTheExtensionPredictsNewFlowers) {
    const PlantedEffect effect = GetParam();
    std::uint32_t named_first = 0, close_to_truth = 0;
    std::vector<double> ratios;
    for (std::uint64_t seed = 1; seed <= seeds; ++seed) {
        const auto train = make_synthetic_trials({.effect = effect, .seed = seed}, shared_predictor());
        const auto result = analyse_discrepancy(analysis_input(train), options_for(seed));
        ASSERT_TRUE(result) << result.error().message;
        const bool first = !result->causes.empty() && result->causes[0].covariate == train.truth.column &&
                           result->causes[0].direction == train.truth.direction;
        named_first += first ? 1 : 0;
        if (!first) {
            std::printf("seed %llu: named %s\n", static_cast<unsigned long long>(seed),
                        result->causes.empty() ? "nothing" : (result->causes[0].covariate + " " + result->causes[0].direction).c_str());
        }
        // New flowers: the extension as the species model applies it, against the generating truth.
        const auto test = make_synthetic_trials({.effect = effect, .seed = seed + 100000}, shared_predictor());
        std::vector<double> fitted;
        for (std::size_t i = 0; i < test.data.trials.size(); ++i) {
            fitted.push_back(std::log(systems::insertion::extension_factor(result->extension, test.data.trials[i].insertion, test.data.covariates_of(i))));
        }
        const double ratio = held_out_rmse(test, fitted) / held_out_rmse(test, test.true_log_factor);
        ratios.push_back(ratio);
        close_to_truth += ratio <= 1.10 ? 1 : 0;
        if (ratio > 1.10) {
            std::printf("seed %llu: held-out RMSE %.3f x the truth's with", static_cast<unsigned long long>(seed), ratio);
            for (const auto& t : result->extension) std::printf(" [%s %s %.3g s=%.3g o=%.3g]", t.covariate.c_str(), t.form.c_str(), t.coefficient, t.scale, t.origin);
            std::printf("\n");
        }
    }
    std::sort(ratios.begin(), ratios.end());
    std::printf("%s: named first in %u / %u seeds; held-out RMSE / truth's: median %.3f, worst %.3f\n", name_of(effect), named_first, seeds,
                ratios[ratios.size() / 2], ratios.back());
    EXPECT_GE(named_first, seeds * 95 / 100);
    EXPECT_GE(close_to_truth, seeds * 95 / 100);
}

INSTANTIATE_TEST_SUITE_P(Kinds, HiddenEffect,
                         ::testing::Values(PlantedEffect::unknown_numeric, PlantedEffect::category, PlantedEffect::insertion_count,
                                           PlantedEffect::step_threshold, PlantedEffect::saturating_decay, PlantedEffect::peaked_optimum),
                         [](const auto& param_info) { return std::string(name_of(param_info.param)); });

TEST(HiddenEffect, NothingIsReportedWhenNothingWasPlanted) {
    std::uint32_t clean = 0;
    for (std::uint64_t seed = 1; seed <= seeds; ++seed) {
        const auto data = make_synthetic_trials({.effect = PlantedEffect::none, .seed = seed}, shared_predictor());
        const auto result = analyse_discrepancy(analysis_input(data), options_for(seed));
        ASSERT_TRUE(result) << result.error().message;
        clean += result->discrepancy_found ? 0 : 1;
        EXPECT_EQ(result->gain == 0.0, !result->discrepancy_found);
        if (result->discrepancy_found) {
            std::printf("seed %llu: reported %s\n", static_cast<unsigned long long>(seed),
                        result->causes.empty() ? "the level" : result->causes[0].covariate.c_str());
        }
    }
    std::printf("no effect: clean in %u / %u seeds\n", clean, seeds);
    EXPECT_GE(clean, seeds * 95 / 100);
}

// Issue 17: two real effects at once (a trend on humidity and a step on storage days): both named with
// their directions, and the extension predicts new flowers within 10 % of the true model's error.
TEST(HiddenEffect, TwoEffectsAtOnceAreBothNamedAndPredictAsTheTruthDoes) {
    std::uint32_t both = 0, close_to_truth = 0, interactions = 0;
    std::vector<double> ratios;
    for (std::uint64_t seed = 1; seed <= seeds; ++seed) {
        const auto train = make_synthetic_trials({.effect = PlantedEffect::two_effects, .seed = seed}, shared_predictor());
        const auto result = analyse_discrepancy(analysis_input(train), options_for(seed));
        ASSERT_TRUE(result) << result.error().message;
        auto named = [&](const std::string& column, const std::string& direction) {
            return std::any_of(result->causes.begin(), result->causes.end(),
                               [&](const Cause& c) { return c.covariate == column && c.direction == direction; });
        };
        const bool ok = named("humidity_pct", "increases") && named("storage_days", "decreases");
        both += ok ? 1 : 0;
        interactions += std::any_of(result->interactions.begin(), result->interactions.end(), [](const InteractionCheck& i) { return i.kept; }) ? 1 : 0;
        const auto test = make_synthetic_trials({.effect = PlantedEffect::two_effects, .seed = seed + 100000}, shared_predictor());
        std::vector<double> fitted;
        for (std::size_t i = 0; i < test.data.trials.size(); ++i) fitted.push_back(std::log(systems::insertion::extension_factor(result->extension, test.data.trials[i].insertion, test.data.covariates_of(i))));
        const double ratio = held_out_rmse(test, fitted) / held_out_rmse(test, test.true_log_factor);
        ratios.push_back(ratio);
        close_to_truth += ratio <= 1.10 ? 1 : 0;
        if (!ok || ratio > 1.10) {
            std::printf("seed %llu: ratio %.3f, causes", static_cast<unsigned long long>(seed), ratio);
            for (const auto& c : result->causes) std::printf(" [%s %s %s]", c.covariate.c_str(), c.direction.c_str(), c.shape.form.c_str());
            std::printf("\n");
        }
    }
    std::sort(ratios.begin(), ratios.end());
    std::printf("two effects: both named in %u / %u seeds; held-out RMSE / truth's: median %.3f, worst %.3f; an interaction kept in %u\n", both, seeds,
                ratios[ratios.size() / 2], ratios.back(), interactions);
    EXPECT_GE(both, seeds * 95 / 100);
    EXPECT_GE(close_to_truth, seeds * 95 / 100);
    EXPECT_LE(interactions, seeds * 5 / 100) << "two effects that add up are not an interaction";
}

// Issue 17: an effect that depends on a second column (humidity matters more the longer the flowers
// were stored; none at day 0) is found as an interaction, and the extension then predicts new flowers
// within 10 % of the truth's error.
TEST(HiddenEffect, AnEffectThatChangesWithASecondColumnIsKeptAsAnInteraction) {
    std::uint32_t found = 0, close_to_truth = 0;
    for (std::uint64_t seed = 1; seed <= seeds; ++seed) {
        const auto train = make_synthetic_trials({.effect = PlantedEffect::interaction, .seed = seed}, shared_predictor());
        const auto result = analyse_discrepancy(analysis_input(train), options_for(seed));
        ASSERT_TRUE(result) << result.error().message;
        const bool ok = std::any_of(result->interactions.begin(), result->interactions.end(), [](const InteractionCheck& i) {
            return i.kept && ((i.covariate == "humidity_pct" && i.times == "storage_days") || (i.covariate == "storage_days" && i.times == "humidity_pct"));
        });
        found += ok ? 1 : 0;
        const auto test = make_synthetic_trials({.effect = PlantedEffect::interaction, .seed = seed + 100000}, shared_predictor());
        std::vector<double> fitted;
        for (std::size_t i = 0; i < test.data.trials.size(); ++i) fitted.push_back(std::log(systems::insertion::extension_factor(result->extension, test.data.trials[i].insertion, test.data.covariates_of(i))));
        const double ratio = held_out_rmse(test, fitted) / held_out_rmse(test, test.true_log_factor);
        close_to_truth += ratio <= 1.10 ? 1 : 0;
        if (!ok || ratio > 1.10) {
            std::printf("seed %llu: ratio %.3f;", static_cast<unsigned long long>(seed), ratio);
            for (const auto& c : result->causes) std::printf(" [%s %s]", c.covariate.c_str(), c.shape.form.c_str());
            for (const auto& i : result->interactions) std::printf(" {%s x %s p %.3g%s}", i.covariate.c_str(), i.times.c_str(), i.p_value, i.kept ? " kept" : "");
            std::printf("\n");
        }
    }
    std::printf("interaction: kept in %u / %u seeds; held-out within 10 %% of the truth's in %u\n", found, seeds, close_to_truth);
    EXPECT_GE(found, seeds * 95 / 100);
    EXPECT_GE(close_to_truth, seeds * 95 / 100);
}

// Issue 17: a small study, 12 flowers of six insertions. A trend within each flower (with the
// insertion count) has 72 rows behind it; one that varies only between flowers (humidity, a flower's
// room) has 12 points, and at the family-wise 1 % the trend of the other kinds (+-12 %) is named in
// about 16 of 40 seeds: it takes +-24 % to be named as reliably as with 60 flowers.
TEST(HiddenEffect, TwelveFlowersAreEnoughForARealTrend) {
    for (const auto& [effect, scale] : {std::pair{PlantedEffect::insertion_count, 1.0}, std::pair{PlantedEffect::unknown_numeric, 2.0}}) {
        std::uint32_t named_first = 0;
        for (std::uint64_t seed = 1; seed <= seeds; ++seed) {
            const auto train = make_synthetic_trials({.effect = effect, .seed = seed, .flowers = 12, .effect_scale = scale}, shared_predictor());
            const auto result = analyse_discrepancy(analysis_input(train), options_for(seed));
            ASSERT_TRUE(result) << result.error().message;
            const bool first = !result->causes.empty() && result->causes[0].covariate == train.truth.column && result->causes[0].direction == train.truth.direction;
            named_first += first ? 1 : 0;
            if (!first) {
                std::printf("%s seed %llu: named %s\n", name_of(effect), static_cast<unsigned long long>(seed),
                            result->causes.empty() ? "nothing" : result->causes[0].covariate.c_str());
            }
        }
        std::printf("12 flowers, %s x%.0f: named first in %u / %u seeds\n", name_of(effect), scale, named_first, seeds);
        EXPECT_GE(named_first, seeds * 95 / 100) << name_of(effect);
    }
}

// Issue 17: no effect, but four near-copies of one column (humidity measured by four sensors): the
// copies must not add up to a false alarm.
TEST(HiddenEffect, NearCopiesOfAColumnRaiseNoFalseAlarm) {
    std::uint32_t clean = 0;
    for (std::uint64_t seed = 1; seed <= seeds; ++seed) {
        const auto data = make_synthetic_trials({.effect = PlantedEffect::none, .seed = seed, .near_copies = 4}, shared_predictor());
        const auto result = analyse_discrepancy(analysis_input(data), options_for(seed));
        ASSERT_TRUE(result) << result.error().message;
        clean += result->discrepancy_found ? 0 : 1;
        if (result->discrepancy_found) {
            std::printf("seed %llu: reported %s\n", static_cast<unsigned long long>(seed), result->causes.empty() ? "the level" : result->causes[0].covariate.c_str());
        }
    }
    std::printf("near-copies, no effect: clean in %u / %u seeds\n", clean, seeds);
    EXPECT_GE(clean, seeds * 95 / 100);
}

// Issue 17: a few percent of gross errors (a slipped gauge, a misread scale) on top of a moderate real
// effect. Without care they swamp it (nothing was reported); the analysis sets them aside, names them,
// and finds the effect. Over the seeds: the effect named first with its direction, the misread rows
// found, hardly a sound row set aside, no false cause.
TEST(HiddenEffect, GrossErrorsAreSetAsideAndNamedAndTheRealEffectIsFound) {
    std::uint32_t named_first = 0, false_causes = 0;
    std::size_t planted = 0, caught = 0, wrongly = 0;
    for (std::uint64_t seed = 1; seed <= seeds; ++seed) {
        const auto train = make_synthetic_trials({.effect = PlantedEffect::gross_outliers, .seed = seed}, shared_predictor());
        const auto result = analyse_discrepancy(analysis_input(train), options_for(seed));
        ASSERT_TRUE(result) << result.error().message;
        const bool first = !result->causes.empty() && result->causes[0].covariate == "humidity_pct" && result->causes[0].direction == "increases";
        named_first += first ? 1 : 0;
        for (const auto& c : result->causes) {
            // dew_point is humidity's correlated bystander; anything else is a false cause.
            if (c.covariate != "humidity_pct" && c.covariate != "dew_point") ++false_causes;
        }
        planted += train.gross_rows.size();
        for (const auto& s : result->suspected) {
            const bool real = std::find(train.gross_rows.begin(), train.gross_rows.end(), s.row) != train.gross_rows.end();
            caught += real ? 1 : 0;
            wrongly += real ? 0 : 1;
        }
        EXPECT_EQ(result->n_trials, train.data.trials.size());
        EXPECT_EQ(result->fitted_log_factor.size(), train.data.trials.size());
        if (!first) std::printf("seed %llu: named %s\n", static_cast<unsigned long long>(seed), result->causes.empty() ? "nothing" : result->causes[0].covariate.c_str());
    }
    std::printf("gross errors: effect named first in %u / %u seeds; %zu of %zu misread rows set aside, %zu sound rows too; %u false causes\n", named_first,
                seeds, caught, planted, wrongly, false_causes);
    EXPECT_GE(named_first, seeds * 95 / 100);
    EXPECT_GE(caught, planted * 95 / 100);
    EXPECT_LE(wrongly, planted / 20);
    EXPECT_EQ(false_causes, 0u);
}

// A flag set only on the misread rows (re-gauged afterwards) has nothing left to test once they are set
// aside: it is left out, not a crash (it was: a candidate with no shape).
TEST(HiddenEffect, AColumnLeftConstantByTheRowsSetAsideIsLeftOut) {
    const auto train = make_synthetic_trials({.effect = PlantedEffect::gross_outliers, .seed = 3}, shared_predictor());
    ASSERT_GE(train.gross_rows.size(), 2u);
    AnalysisInput in = analysis_input(train);
    CovariateColumn flag;
    flag.name = "regauged";
    flag.values.assign(in.measured_gf.size(), 0.0);
    for (std::size_t r : train.gross_rows) flag.values[r] = 1.0;
    in.covariates.columns.push_back(flag);
    const auto result = analyse_discrepancy(in, options_for(3));
    ASSERT_TRUE(result) << result.error().message;
    EXPECT_EQ(result->suspected.size(), train.gross_rows.size());
    EXPECT_TRUE(std::none_of(result->diagnostics.begin(), result->diagnostics.end(), [](const CovariateDiagnostic& d) { return d.covariate == "regauged"; }));
    // An infinite force is refused naming its row, not set aside as an outlier.
    in.measured_gf[7] = INFINITY;
    const auto refused = analyse_discrepancy(in, options_for(3));
    ASSERT_FALSE(refused);
    EXPECT_NE(refused.error().message.find("row 8:"), std::string::npos) << refused.error().message;
}

// Issue 19: a lab's file with a lot number given row by row (10,000 levels, about one row each) beside
// a real effect on one of 12 stations. The lot number is screened out, with its reason and the share
// of the residual's variance between its levels, which is what chance gives that many levels; nothing
// per level is built for it, and the station is still named.
TEST(HiddenEffect, APlantedTwelveLevelEffectIsFoundBesideATenThousandLevelBystander) {
    const auto train = make_synthetic_trials({.effect = PlantedEffect::station, .seed = 3, .flowers = 1700, .insertions = 6, .wide_levels = 10000},
                                             shared_predictor());
    AnalysisOptions o = options_for(3);
    o.permutations = 200;
    o.bootstrap = 50;
    const auto result = analyse_discrepancy(analysis_input(train), o);
    ASSERT_TRUE(result) << result.error().message;
    ASSERT_EQ(result->screened.size(), 1u);
    const auto& lot = result->screened[0];
    EXPECT_EQ(lot.covariate, "batch");
    EXPECT_EQ(lot.levels, 10000u);
    EXPECT_NE(lot.reason.find("10000 levels, more than the 200"), std::string::npos) << lot.reason;
    EXPECT_NEAR(lot.between_level_share, lot.chance_share, 0.05) << "the lot number carries nothing beyond chance";
    EXPECT_TRUE(std::none_of(result->diagnostics.begin(), result->diagnostics.end(), [](const CovariateDiagnostic& d) { return d.covariate == "batch"; }));
    ASSERT_FALSE(result->causes.empty());
    EXPECT_EQ(result->causes[0].covariate, "station");
    EXPECT_EQ(result->causes[0].category, "S07");
    EXPECT_EQ(result->causes[0].direction, "decreases");
}

// A column whose levels are each seen on about one flower (a sample id) is screened even when it has
// few levels in all: its per-level effect could not be told from the flowers' own differences.
TEST(HiddenEffect, AColumnNestedInFlowersIsScreenedAndSaidWhy) {
    // A lot per flower (its six rows): 60 levels, each on one flower.
    auto train = make_synthetic_trials({.effect = PlantedEffect::none, .seed = 5, .flowers = 60, .insertions = 6, .wide_levels = 60, .rows_per_lot = 6},
                                       shared_predictor());
    const auto result = analyse_discrepancy(analysis_input(train), options_for(5));
    ASSERT_TRUE(result) << result.error().message;
    ASSERT_EQ(result->screened.size(), 1u);
    EXPECT_EQ(result->screened[0].covariate, "batch");
    EXPECT_NE(result->screened[0].reason.find("flowers each on average"), std::string::npos) << result->screened[0].reason;
}

// The analysis' memory budget: an input whose working memory would be more is refused, naming the
// column that needs most and what to do, before anything is allocated. A categorical column is a factor
// held as its levels' means: 150 levels cost 150^2 numbers, not 149 columns of 3,600 rows (12.9 MB in
// the three copies a numeric column has), so it is the numeric columns with their many shapes that the
// budget meets first.
TEST(HiddenEffect, AnInputBeyondTheMemoryBudgetIsRefusedNamingItsWidestColumn) {
    // 150 lots over 3,600 rows, each on about 24 flowers: testable level by level.
    const auto train = make_synthetic_trials({.effect = PlantedEffect::none, .seed = 7, .flowers = 600, .insertions = 6, .wide_levels = 150},
                                             shared_predictor());
    AnalysisOptions o = options_for(7);
    o.memory_budget_bytes = 4 << 20;
    o.search_rows = 0; // every row or nothing: no sample
    const auto result = analyse_discrepancy(analysis_input(train), o);
    ASSERT_FALSE(result);
    EXPECT_NE(result.error().message.find("KiB of working memory, more than the 4096 KiB budget; the widest is the column 'speed_mm_s': leave it out (--ignore speed_mm_s) or split the file"),
              std::string::npos)
        << result.error().message;

    // The lot number alone fits the same budget and is tested.
    AnalysisInput only_batch = analysis_input(train);
    std::erase_if(only_batch.covariates.columns, [](const CovariateColumn& c) { return c.name != "batch"; });
    ASSERT_EQ(only_batch.covariates.columns.size(), 1u);
    o.permutations = 200;
    const auto batch = analyse_discrepancy(only_batch, o);
    ASSERT_TRUE(batch) << batch.error().message;
    EXPECT_TRUE(batch->screened.empty());
    ASSERT_EQ(batch->diagnostics.size(), 1u);
    EXPECT_GT(batch->diagnostics[0].p_value, 0.01) << "no effect was planted";
}

// Long data (issue 40): beyond AnalysisOptions::search_rows the search for causes runs on a random
// sample of whole flowers, and the model it chose is fitted on every row. The sample holds whole
// flowers (six rows each here), the planted cause is named, and every row has its own fitted value.
TEST(HiddenEffect, ALongFilesSearchRunsOnASampleOfWholeFlowersAndItsModelIsFittedOnEveryRow) {
    const auto train = make_synthetic_trials({.effect = PlantedEffect::unknown_numeric, .seed = 41, .flowers = 600, .insertions = 6}, shared_predictor());
    AnalysisOptions o = options_for(41);
    o.search_rows = 900;
    const auto result = analyse_discrepancy(analysis_input(train), o);
    ASSERT_TRUE(result) << result.error().message;
    ASSERT_TRUE(result->sample.has_value());
    EXPECT_GE(result->sample->rows, 900u);
    EXPECT_LT(result->sample->rows, 906u);
    EXPECT_EQ(result->sample->rows % 6, 0u) << "whole flowers";
    EXPECT_EQ(result->sample->flowers, result->sample->rows / 6);
    EXPECT_EQ(result->n_trials, 3600u);
    EXPECT_EQ(result->n_flowers, 600u);
    ASSERT_EQ(result->fitted_log_factor.size(), 3600u);
    ASSERT_EQ(result->cv_log_factor.size(), 3600u);
    ASSERT_FALSE(result->causes.empty());
    EXPECT_EQ(result->causes[0].covariate, "humidity_pct");
    EXPECT_EQ(result->causes[0].direction, "increases");
    EXPECT_LT(result->extended_cv_rmse_gf, result->baseline_cv_rmse_gf);
    // Every row's check of the columns left out finds nothing: nothing else was planted.
    for (std::size_t k = 0; k < result->sample->columns.size(); ++k) {
        EXPECT_LE(result->sample->z[k], result->sample->z_needed) << result->sample->columns[k];
    }
    EXPECT_NE(result->log.front().find("the search for causes ran on a random 150 of 600 flowers"), std::string::npos) << result->log.front();

    // The same file under the sample size: every row is searched, and nothing says otherwise.
    o.search_rows = 3600;
    const auto whole = analyse_discrepancy(analysis_input(train), o);
    ASSERT_TRUE(whole) << whole.error().message;
    EXPECT_FALSE(whole->sample.has_value());
}

// A sample can miss what every row shows: with 19 permutations no p-value can fall below 0.05, so the
// sample's search names nothing at alpha 0.01, and the check on every row says humidity carries a
// trend the sample did not find.
TEST(HiddenEffect, AnEffectTheSampleCannotFindIsFlaggedByEveryRow) {
    const auto train = make_synthetic_trials({.effect = PlantedEffect::unknown_numeric, .seed = 42, .flowers = 600, .insertions = 6}, shared_predictor());
    AnalysisOptions o = options_for(42);
    o.search_rows = 600;
    o.permutations = 19;
    const auto result = analyse_discrepancy(analysis_input(train), o);
    ASSERT_TRUE(result) << result.error().message;
    ASSERT_TRUE(result->sample.has_value());
    EXPECT_TRUE(result->causes.empty());
    const auto& s = *result->sample;
    const auto at = std::find(s.columns.begin(), s.columns.end(), "humidity_pct");
    ASSERT_NE(at, s.columns.end());
    EXPECT_GT(s.z[static_cast<std::size_t>(at - s.columns.begin())], s.z_needed);
}
