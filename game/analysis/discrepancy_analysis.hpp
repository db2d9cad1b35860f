#pragma once
// Where the simulation disagrees with measured insertions, why, and a fitted extension that fixes it
// (docs/measured-data.md, "How validate decides"). The input is the measured force, the simulation's
// prediction and the candidate covariates of every trial; the analysis knows nothing about any
// column beyond its values.
//
// Everything is on the log scale: forces are positive and the effects are multiplicative, so the
// residual is r = ln(measured / predicted) and an extension multiplies the force by exp(sum of terms).
//  - Tests: a covariate's statistic is the largest share of the current residual that one of its
//    shapes explains (a category: its whole block), after the accepted terms; a numeric column with a
//    straight line is scored by the larger surprise of that and of its line alone, alpha split 1:4
//    between them (discrepancy_permutation_test.cpp, "line_share"). Its null distribution
//    comes from permuting the residual while keeping each flower's rows together: flower means are
//    permuted among flowers, and deviations within each flower. p-values are corrected for the
//    family of covariates by Westfall-Young step-down maxT (the permutation form of Holm's method,
//    which keeps the dependence between correlated columns); the kept terms' final p-values by Holm.
//    The overall level is tested on its own, by sign flips of whole flowers.
//  - Forward selection judges each candidate given the terms already accepted; a term is accepted
//    only when it is significant after correction AND its best form (chosen by grouped
//    cross-validation) lowers the cross-validated error. A backward pass then re-tests every accepted
//    term given all the others and drops any that no longer holds: a correlated bystander accepted
//    early does not survive the real cause.
//  - Cross-validation folds never split a flower. With fewer than 4 flowers (the paper's table has
//    one row per insertion count), rows stand in for flowers and the report says so.
#include <cmath>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "components/insertion.hpp"
#include "engine/core/result.hpp"
#include "game/analysis/covariate_columns.hpp"
#include "game/analysis/term_shapes.hpp"

namespace ikebana::game {

// What the rows measured. Forces (the usual case) are compared on the log scale, r = ln(measured /
// predicted). Outcomes (issue 57) are compared as the fall minus its predicted chance, r = fell - p:
// measured_gf then holds 1 for a fall and 0 for a stand, predicted_gf the simulation's chance of
// falling, every stage runs on that residual unchanged (an extension adds to the chance), and the
// cross-validated error that chooses shapes and accepts terms is the log-loss of the chance, kept
// within [0.001, 0.999], instead of the squared error.
enum class Observed { force, outcome };

struct AnalysisInput {
    std::vector<std::string> flower;    // per row: which physical flower
    std::vector<double> measured_gf;    // > 0 (outcome: 1 fell, 0 stood)
    std::vector<double> predicted_gf;   // > 0, the simulation's (outcome: its chance of falling)
    CovariateSet covariates;
    Observed observed = Observed::force;
};

// Row i's residual, what the analysis explains: ln(measured / predicted), or fell - chance.
inline double residual_of(const AnalysisInput& in, std::size_t i) {
    return in.observed == Observed::outcome ? in.measured_gf[i] - in.predicted_gf[i] : std::log(in.measured_gf[i] / in.predicted_gf[i]);
}
// The held-out loss of row i given the model's value there: squared error of the residual, or the
// outcome's log-loss at the chance moved by it.
double held_out_loss(const AnalysisInput& in, std::size_t i, double model);

// Permutations of a stage's tests, or (stage == bootstrap_stage) the flower resamples of the intervals.
using AnalysisProgress = std::function<void(const std::string& stage, std::uint32_t done, std::uint32_t of)>;
inline constexpr const char* bootstrap_stage = "intervals";

struct AnalysisOptions {
    std::uint32_t permutations = 1000;
    double alpha = 0.01;          // family-wise: a false alarm costs a researcher more than a missed 2 % effect
    std::uint64_t seed = 1;
    std::uint32_t folds = 10;     // grouped CV; fewer when there are fewer flowers
    std::uint32_t bootstrap = 200; // flower resamples for the intervals
    std::uint32_t max_terms = 4;
    // A categorical column is tested level by level only when its levels are seen, on average, on at
    // least this many flowers each and there are at most max_levels of them; otherwise it is screened
    // out (AnalysisResult::screened says so, with its between-level variance).
    double min_flowers_per_level = 3.0;
    std::size_t max_levels = 200;
    // The analysis' working memory (its design columns, each a row long, and their copies): an input
    // that would need more is refused naming its widest column, instead of swapping.
    std::size_t memory_budget_bytes = std::size_t{1} << 30;
    // Long data: the search for causes (tests, forms, selection, interactions) runs on a random sample
    // of whole flowers of about this many rows (fewer when the budget needs it), the final fit, its
    // intervals and its cross-validated gain on every row; 0: every row, within the budget. On this
    // machine 60,000 rows of 7 numeric columns take 14 s to search (docs/benchmarks.md).
    std::size_t search_rows = 60000;
    // Gross errors (a slipped gauge, a misread scale): a row whose ln(measured / model) lies more than
    // this many robust standard deviations (1.4826 x the median absolute deviation) from the median of all rows is
    // set aside, said so, and the analysis runs without it; 0 turns it off. Checked on the baseline's
    // residual, then once more on the fitted model's (an effect widens the first). Needs 20 rows.
    double outlier_z = 5.0;
    AnalysisProgress progress;
};

// A categorical column that cannot carry a testable per-level effect (a lot number, a sample id, a
// note): not tested, and said so. Its levels' means are still summarised as a random effect would be:
// the share of the residual's variance between its levels, beside the share chance alone gives.
struct ScreenedColumn {
    std::string covariate;
    std::size_t levels = 0;
    double flowers_per_level = 0.0;   // distinct flowers a level is seen on, on average
    double between_level_share = 0.0; // of the baseline residual's variance, by its levels' means
    double chance_share = 0.0;        // what that share is expected to be with no effect: (levels - 1) / (rows - 1)
    std::string reason;
};

struct ResidualBin {
    std::string label;   // "1", "[2.5, 4.1)", or a category
    double x = 0.0;      // the bin's mean covariate value (numeric)
    std::size_t n = 0;
    double factor = 1.0; // exp(mean residual): measured / predicted in the bin
    double low = 1.0, high = 1.0; // +- 2 standard errors
};

struct CovariateDiagnostic {
    std::string covariate;
    bool numeric = true;
    std::vector<ResidualBin> bins;   // the residual's shape against this covariate
    double strength = 0.0;           // share of the baseline residual's variance its best shape explains
    std::string best_shape;          // that shape; for a cause, the shape it was fitted with
    double p_value = 1.0;            // against the baseline residual, permutation
    double p_adjusted = 1.0;         // family-wise over all covariates
    double p_given_model = 1.0;      // against the final model's residual (family-wise there)
    bool cause = false;              // kept in the final model
    std::size_t blank = 0;           // rows with an empty cell: numeric ones take the middle of the
    double blank_value = 0.0;        //   column's range (that value); categorical ones are the level "(missing)"
};

struct Cause {
    std::string covariate;
    std::string direction;    // increases, decreases, nonmonotone
    TermShape shape;
    std::string category;     // categorical: the level that differs most from the other levels
    std::string reference;    // categorical: the level the coefficients are relative to (most common)
    std::vector<double> level_share; // categorical: share of the rows at each level
    double x_low = 0.0, x_high = 0.0; // numeric: the range the effect size spans (5th-95th percentile)
    double effect_size = 0.0;  // relative change of the force across that range (categorical: the level
                               // that differs most against the row-weighted mean of the others)
    double effect_low = 0.0, effect_high = 0.0; // 95 % interval, flower bootstrap
    double p_value = 1.0;      // given all other terms, Holm-adjusted over the kept terms
    double importance = 0.0;   // share of the residual variance lost when the term is dropped
    std::vector<double> curve_x, curve_factor; // the fitted factor across the covariate (for plots)
    Eigen::VectorXd coefficients;
};

// A row set aside as a suspected gross error.
struct SuspectRow {
    std::size_t row = 0;     // index into the input
    double measured_gf = 0.0;
    double expected_gf = 0.0; // the simulation times the fitted model at that row
    double z = 0.0;          // robust standard deviations from the median of all rows, against the model it was last judged by
};

// A kept cause's effect that changes with a second column: the cause's basis times (that column -
// its mean), tested for every kept numeric cause against every other numeric column.
struct InteractionCheck {
    std::string covariate;   // the cause
    std::string times;       // the column its effect changes with
    double p_value = 1.0;    // family-wise over the pairs tested
    bool kept = false;       // significant and lowered the cross-validated error: a term of the extension
    double coefficient = 0.0; // when kept
};

// A search run on a sample of flowers (AnalysisOptions::search_rows), and what every row says about
// the columns the sample left out: each one's linear and curved trend against the final model's
// residual, as a z with flower-clustered errors (rows of a flower are not independent). A column
// beyond `z_needed` carries an effect the sample was too small to find.
struct SearchSample {
    std::size_t rows = 0, flowers = 0;       // the sample's
    double z_needed = 0.0;                   // two-sided, Bonferroni over the columns and both trends at alpha
    std::vector<std::string> columns;        // the numeric columns not in the model
    std::vector<double> z;                   // per column: the larger |z| of its two trends, on every row
};

struct Calibration {
    double factor = 1.0;         // geometric mean of measured / predicted the extended model applies
    double low = 1.0, high = 1.0; // 95 % interval
    double p_value = 1.0;        // the baseline's overall level against 1 (flower sign flips)
    bool significant = false;
};

struct AnalysisResult {
    std::size_t n_trials = 0;
    std::size_t n_flowers = 0;
    bool rows_as_groups = false;  // fewer than 4 flowers: rows stood in for flowers
    std::uint32_t folds = 0;
    double baseline_rmse_gf = 0.0;
    double baseline_cv_rmse_gf = 0.0;
    double baseline_log_rmse = 0.0;
    double extended_rmse_gf = 0.0;
    double extended_cv_rmse_gf = 0.0;
    double extended_log_rmse = 0.0;
    double gain = 0.0;            // 1 - extended CV RMSE / baseline CV RMSE; 0 when nothing is found
    bool discrepancy_found = false;
    Calibration calibration;
    std::vector<CovariateDiagnostic> diagnostics; // every candidate tested, in the file's order
    std::vector<ScreenedColumn> screened;         // categorical columns too wide to test level by level
    std::vector<Cause> causes;                    // by importance
    std::vector<InteractionCheck> interactions;   // pairs tested (significant ones first)
    std::vector<components::DeteriorationTerm> extension; // exp(sum) multiplies the force; empty: none
    std::vector<SuspectRow> suspected;            // rows set aside (AnalysisOptions::outlier_z); the figures
                                                  // above are on the other rows, n_trials counts them all
    std::vector<double> fitted_log_factor;        // per row, in sample (a suspected row: the model's value)
    std::vector<double> cv_log_factor;            // per row, from the fold that held the row out
    std::vector<std::string> log;                 // what each step decided, for the report
    std::optional<SearchSample> sample;           // set when the search ran on a sample of flowers
};

Result<AnalysisResult> analyse_discrepancy(const AnalysisInput& input, const AnalysisOptions& options);

// The input at `rows` (sorted, each once); a categorical column keeps the whole input's levels, so a
// level means the same in both.
AnalysisInput input_rows(const AnalysisInput& in, const std::vector<std::size_t>& rows);

} // namespace ikebana::game
