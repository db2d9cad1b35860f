// The search on outcomes (issue 57): effects on standing and falling hidden in synthetic trials must be
// found through the data alone (fell minus the simulated chance), with the direction they have, and the
// correction must predict falls on rows it was not fitted to nearly as well as the truth does. Without
// an effect (flowers that differ only by themselves) nothing may be named.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>

#include "game/analysis/discrepancy_analysis.hpp"

using namespace ikebana::game;

namespace {

enum class Hidden { unseen_column, angle_law, depth, none, weak_unseen };

const char* name_of(Hidden h) {
    switch (h) {
    case Hidden::unseen_column: return "unseen_column";
    case Hidden::angle_law: return "angle_law";
    case Hidden::depth: return "depth";
    case Hidden::none: return "none";
    case Hidden::weak_unseen: return "weak_unseen";
    }
    return "?";
}

double logistic(double x) { return 1.0 / (1.0 + std::exp(-x)); }

// Trials as a researcher's table holds them: 80 flowers of 6 insertions, each at its own angle and
// depth; a column the model never reads (the stem's water content, per flower) and a bystander (the
// bench's temperature, per row). The simulation's chance of falling rises with the angle past 40
// degrees and with the insertions; the truth adds the hidden effect, and each flower's own tendency
// (a random effect of 0.08 in chance) when `spread`.
struct OutcomeTrials {
    AnalysisInput input;
    std::vector<double> true_chance;
    std::string column;   // the hidden effect's column ("" for none)
    double direction = 0; // +1: falls more as it rises, -1 less; 0: a bump (named is enough)
};

OutcomeTrials make_trials(Hidden hidden, std::uint64_t seed, bool spread) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::normal_distribution<double> normal(0.0, 1.0);
    OutcomeTrials t;
    t.input.observed = Observed::outcome;
    const auto column = [](const char* name) {
        CovariateColumn c;
        c.name = name;
        return c;
    };
    CovariateColumn insertion = column("insertion"), angle = column("angle_deg"), depth = column("depth_mm"), water = column("water_content"),
                    bench = column("bench_temp_c");
    for (int f = 0; f < 80; ++f) {
        const double w = u(rng);
        const double own = spread ? 0.08 * normal(rng) : 0.0;
        for (int k = 1; k <= 6; ++k) {
            const double a = 20.0 + 45.0 * u(rng);
            const double d = 5.0 + 20.0 * u(rng);
            const double simulated = logistic((a - 40.0) / 6.0 + 0.3 * (k - 3.5));
            double truth = simulated + own;
            switch (hidden) {
            case Hidden::unseen_column: truth += 0.4 * (w - 0.5); break;
            case Hidden::weak_unseen: truth += 0.2 * (w - 0.5); break;
            case Hidden::angle_law: truth = logistic((a - 32.0) / 6.0 + 0.3 * (k - 3.5)) + own; break; // they fall from 32 degrees, not 40
            case Hidden::depth: truth += d < 10.0 ? 0.35 : 0.0; break;                             // too shallow, it falls (Fig. 12(c))
            case Hidden::none: break;
            }
            truth = std::clamp(truth, 0.01, 0.99);
            t.input.flower.push_back("f" + std::to_string(f));
            t.input.measured_gf.push_back(u(rng) < truth ? 1.0 : 0.0);
            t.input.predicted_gf.push_back(simulated);
            t.true_chance.push_back(truth);
            insertion.values.push_back(k);
            angle.values.push_back(a);
            depth.values.push_back(d);
            water.values.push_back(w);
            bench.values.push_back(18.0 + 6.0 * u(rng));
        }
    }
    t.input.covariates.columns = {insertion, angle, depth, water, bench};
    switch (hidden) {
    case Hidden::unseen_column:
    case Hidden::weak_unseen: t.column = "water_content", t.direction = 1; break;
    case Hidden::angle_law: t.column = "angle_deg", t.direction = 0; break; // between 32 and 50 degrees they fall more than simulated: a bump, either way
    case Hidden::depth: t.column = "depth_mm", t.direction = -1; break;
    case Hidden::none: break;
    }
    return t;
}

double log_loss(const AnalysisInput& in, const std::vector<double>& chance) {
    double s = 0.0;
    for (std::size_t i = 0; i < chance.size(); ++i) s += held_out_loss(in, i, chance[i] - in.predicted_gf[i]);
    return s / static_cast<double>(chance.size());
}

AnalysisOptions options_for(std::uint64_t seed) {
    AnalysisOptions o;
    o.seed = seed;
    o.permutations = 500;
    o.bootstrap = 60;
    return o;
}

constexpr std::uint64_t seeds = 40;

class OutcomeEffect : public ::testing::TestWithParam<Hidden> {};

} // namespace

TEST_P(OutcomeEffect, IsNamedFirstWithItsDirectionAndTheCorrectionPredictsFallsOnHeldOutRowsNearlyAsTheTruthDoes) {
    const Hidden hidden = GetParam();
    std::uint64_t named = 0, wrong = 0;
    double gain_sum = 0.0, truth_gain_sum = 0.0;
    for (std::uint64_t seed = 1; seed <= seeds; ++seed) {
        const OutcomeTrials t = make_trials(hidden, seed, hidden == Hidden::weak_unseen);
        const auto result = analyse_discrepancy(t.input, options_for(seed));
        ASSERT_TRUE(result) << result.error().message;
        const bool first = !result->causes.empty() && result->causes[0].covariate == t.column &&
                           (t.direction == 0 || (t.direction > 0 ? result->causes[0].effect_size > 0.0 : result->causes[0].effect_size < 0.0));
        named += first ? 1 : 0;
        wrong += !first && !result->causes.empty() ? 1 : 0;
        if (!first) {
            std::printf("%s seed %llu: named %s\n", name_of(hidden), static_cast<unsigned long long>(seed),
                        result->causes.empty() ? "nothing" : result->causes[0].covariate.c_str());
        }
        // Held out: each row's chance corrected by the fit that did not see its fold, against the truth's.
        std::vector<double> corrected(t.true_chance.size());
        for (std::size_t i = 0; i < corrected.size(); ++i) {
            corrected[i] = t.input.predicted_gf[i] + (result->discrepancy_found ? result->cv_log_factor[i] : 0.0);
        }
        const double before = log_loss(t.input, t.input.predicted_gf);
        gain_sum += before - log_loss(t.input, corrected);
        truth_gain_sum += before - log_loss(t.input, t.true_chance);
    }
    std::printf("%s: named first with its direction in %llu / %llu seeds; held-out log-loss gain %.4f against the truth's %.4f (%.0f %%)\n",
                name_of(hidden), static_cast<unsigned long long>(named), static_cast<unsigned long long>(seeds), gain_sum / static_cast<double>(seeds),
                truth_gain_sum / static_cast<double>(seeds), 100.0 * gain_sum / truth_gain_sum);
    ::testing::Test::RecordProperty("named_first", static_cast<int>(named));
    ::testing::Test::RecordProperty("gain_share_of_truth_percent", static_cast<int>(std::lround(100.0 * gain_sum / truth_gain_sum)));
    EXPECT_LE(wrong, seeds / 20) << "another column named first, or the right one the wrong way";
    if (hidden == Hidden::weak_unseen) {
        // Half the effect under flowers that differ by themselves: 80 flowers give a test of it about a
        // fifth of the power (docs/measured-data.md). Found at times, never mistaken for another column.
        EXPECT_GE(named, seeds / 10);
    } else {
        EXPECT_GE(named, seeds * 17 / 20);
        EXPECT_GE(gain_sum, 0.6 * truth_gain_sum) << "the correction predicts held-out falls at least 60 % as much better as the truth does";
    }
    EXPECT_GT(gain_sum, 0.0);
}

INSTANTIATE_TEST_SUITE_P(OutcomeSearch, OutcomeEffect,
                         ::testing::Values(Hidden::unseen_column, Hidden::angle_law, Hidden::depth, Hidden::weak_unseen),
                         [](const auto& param_info) { return std::string(name_of(param_info.param)); });

TEST(OutcomeSearch, FlowersThatDifferOnlyByThemselvesNameNoColumn) {
    std::uint64_t false_alarms = 0;
    for (std::uint64_t seed = 1; seed <= seeds; ++seed) {
        const OutcomeTrials t = make_trials(Hidden::none, seed, true);
        const auto result = analyse_discrepancy(t.input, options_for(seed));
        ASSERT_TRUE(result) << result.error().message;
        if (!result->causes.empty()) {
            ++false_alarms;
            std::printf("null seed %llu: named %s, p = %.3g\n", static_cast<unsigned long long>(seed), result->causes[0].covariate.c_str(),
                        result->causes[0].p_value);
        }
    }
    ::testing::Test::RecordProperty("false_alarms", static_cast<int>(false_alarms));
    // At a family-wise 1 %, forty seeds should see about 0.4; two are allowed for the flowers' own spread.
    EXPECT_LE(false_alarms, 2u);
}

TEST(OutcomeSearch, AnOutcomeThatIsNeitherZeroNorOneIsRefusedNamingItsRow) {
    OutcomeTrials t = make_trials(Hidden::none, 1, false);
    t.input.measured_gf[4] = 0.5;
    const auto result = analyse_discrepancy(t.input, options_for(1));
    ASSERT_FALSE(result);
    EXPECT_NE(result.error().message.find("row 5: an outcome is 0 or 1"), std::string::npos) << result.error().message;
}
