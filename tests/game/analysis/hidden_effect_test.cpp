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
        for (const auto& t : test.data.trials) {
            fitted.push_back(std::log(systems::insertion::extension_factor(result->extension, t.insertion, t.covariates)));
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
                                           PlantedEffect::step_threshold, PlantedEffect::saturating_decay),
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
