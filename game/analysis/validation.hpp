#pragma once
// `ikebana validate` without the command line: measured trials in, the simulation's predictions for
// them, the discrepancy analysis, the extended species, and the extended species run back through the
// simulation to measure the gain where it matters (forces and outcomes of the live systems).
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "engine/core/result.hpp"
#include "game/analysis/discrepancy_analysis.hpp"
#include "game/analysis/insertion_predictor.hpp"
#include "game/analysis/measured_data.hpp"

namespace ikebana::game {

struct ValidationOptions {
    std::string species_override;      // id or file for every row
    std::vector<std::string> ignore;    // columns that are not covariates (say, the force restated)
    AnalysisOptions analysis;
    // Run the extended species through the simulation for every row (skipped above this many
    // distinct conditions, where `predict --species EXT.json` does it at leisure).
    std::size_t resimulate_limit = 400;
    std::function<void(const std::string& stage, std::size_t done, std::size_t of)> progress;
};

// A quantity measured besides the forces the extension was fitted to (the paper's experiment means,
// an `outcome` column's accuracy), before and after the extension. A model fitted to one observable
// and broken on another is no improvement: `worse` says the extension moved this one clearly away
// from its measurement (further than the baseline by more than `tolerance`).
struct OtherMeasure {
    std::string name;     // "insertions until the flower falls (the paper's experiment)"
    double measured = 0.0;
    double baseline = 0.0;
    double extended = 0.0;
    double tolerance = 0.0;
    bool worse = false;
    bool error = false;   // an error (measured is its ideal, 0): said as "with the extension, without"
};
OtherMeasure judge_other_measure(std::string name, double measured, double baseline, double extended, double tolerance);
// One sentence: "... 16.0 against the measured 5.8 (the baseline 6.8): the extension makes it clearly worse".
std::string other_measure_words(const OtherMeasure& m);

// A file of several species: each one's rows, held out, without and with the extension found on
// all rows; and when that extension makes one clearly worse, each species' own search on its rows
// alone (an effect of one species is not the model's for all).
struct SpeciesCheck {
    std::string species;
    std::size_t rows = 0;
    double baseline_rmse_gf = 0.0;       // the simulation alone
    double shared_cv_rmse_gf = 0.0;      // with the extension fitted on every species' rows
    std::optional<AnalysisResult> own;   // its own search (when the shared extension was worse somewhere)
    std::string extended_species_json;   // what --write-species writes for it (empty: nothing found)
};

// How well predicted chances of falling match the stood/fell rows: the share called right (a chance
// above one half is a fall), the Brier score (mean squared difference between the chance and 1 for a
// fall, 0 for a stand: 0 perfect, 0.25 a coin) and the log-loss (mean -ln of the chance given to what
// happened, the chance kept within [0.001, 0.999]: ln 2 = 0.693 a coin). Rows whose outcome is neither
// (broke, blank) are not scored.
struct OutcomeScores {
    double accuracy = 0.0;
    double brier = 0.0;
    double log_loss = 0.0;
    std::size_t rows = 0;
};
[[nodiscard]] std::optional<OutcomeScores> score_outcomes(const MeasuredData& data, const std::vector<double>& fall_probability);

// Calibration: the stood/fell rows grouped by their predicted chance of falling (bins 0-0.1, 0.1-0.3,
// 0.3-0.5, 0.5-0.7, 0.7-0.9, 0.9-1), each bin's mean chance against the share that fell. A calibrated
// model's bins lie on the diagonal.
struct CalibrationBin {
    double low = 0.0, high = 0.0; // the bin's chances
    std::size_t rows = 0;
    double predicted = 0.0;       // the rows' mean predicted chance
    double fell = 0.0;            // the share of them that fell
    double se = 0.0;              // its binomial standard error
};
[[nodiscard]] std::vector<CalibrationBin> calibration_bins(const MeasuredData& data, const std::vector<double>& fall_probability);

// How much the flowers differ by themselves, beyond the model (issue 57): one-way random effects by
// the method of moments on each row's residual, ln(measured / simulated) less the fitted model's log
// factor. sd_log is the flower effect's standard deviation (ln units: 0.12 is about +-12 %), within_sd_log
// the rows' own scatter about their flower's mean. Nothing when fewer than 3 flowers have 2 rows or more.
struct FlowerSpread {
    double sd_log = 0.0;
    double within_sd_log = 0.0;
    std::size_t flowers = 0;
    std::size_t rows = 0;
};
[[nodiscard]] std::optional<FlowerSpread> flower_spread(const std::vector<std::string>& flower, const std::vector<double>& residual_log);

// A column that says what the simulation gets wrong about standing and falling (issue 57): the outcome
// search's cause, its effect as the change in the chance of falling across the column's 5th-95th
// percentile (a count: its least to its most; categorical: the level set apart), with the flower
// bootstrap's 95 % interval and its p-value given the other terms.
struct OutcomeCause {
    std::string covariate;
    std::string category;   // categorical: the level that falls more or less than the others
    std::string direction;  // "falls more" or "falls less" (with the column, or at the level)
    std::string shape;
    double x_low = 0.0, x_high = 0.0;
    double effect = 0.0, effect_low = 0.0, effect_high = 0.0; // change in the chance of falling
    double p_value = 1.0;
};

// The search on outcomes: every candidate column against what the simulation gets wrong about falls
// (fell minus the predicted chance), with the forces' machinery (discrepancy_analysis.hpp, Observed::outcome).
struct OutcomeSearch {
    std::vector<std::size_t> rows;     // the data's rows it ran on: those that stood or fell
    AnalysisInput input;               // their falls, chances and columns
    AnalysisResult analysis;
    std::vector<OutcomeCause> causes;  // by importance
    OutcomeScores baseline;            // the simulation's chance on those rows
    OutcomeScores held_out;            // with the search's correction, each row from the fold that held it out
    // The correction made a holding the simulation can run: the search's terms (its level, its causes)
    // as terms on what holds a stem at rest ("applies_to": "hold"), their coefficients fitted to the
    // falls through each row's simulated chance at several holdings (HoldCurve), and the log-loss the
    // fit reaches on those curves.
    std::vector<components::DeteriorationTerm> hold_terms;
    double hold_fit_log_loss = 0.0;
    // Run through the simulation, that holding predicted the falls worse than the species without it:
    // left out of the species written (hold_simulated: what it gave).
    bool hold_rejected = false;
    OutcomeScores hold_simulated;
    bool hold_fitted = false;  // the fit ran (one species, within the simulation budget)
    std::string hold_note;     // why no holding was fitted or kept, when none was
};
// Runs the outcome search when the data hold enough stood/fell rows of both kinds; otherwise says why
// not in `note`.
std::optional<OutcomeSearch> search_outcomes(const MeasuredData& data, const AnalysisInput& forces, const std::vector<double>& fall_probability,
                                             const AnalysisOptions& options, std::string& note);

// A row's chance of falling with what holds its stem at rest multiplied by a factor, simulated at a few
// factors (hold_curve_factors, and 1): ln factor and chance, ln factor rising. Elsewhere the chance is
// the nearest simulated factor's (ln scale), and unknown (NaN) beyond the ends by more than half an
// end gap. Not interpolated: a row's chance is nearly a step in the
// factor (its 16 placements stand or fall), and a straight line between a 0 and a 1 made chances in
// between that the simulation never gives, which a fit then chose for their log-loss.
struct HoldCurve {
    std::vector<double> log_factor, chance;
};
inline constexpr double hold_curve_factors[] = {0.5, 0.6, 0.7, 0.85, 1.2, 1.4, 1.7, 2.0};
[[nodiscard]] double chance_at(const HoldCurve& curve, double log_factor);
// The outcome search's terms as terms on the holding, fitted to the falls: coordinate descent on the
// log-loss of each row's chance at hold factor exp(sum of the terms). `curves`: one per row of `rows`.
std::vector<components::DeteriorationTerm> fit_hold_terms(const MeasuredData& data, const std::vector<std::size_t>& rows,
                                                          const std::vector<components::DeteriorationTerm>& terms,
                                                          const std::vector<HoldCurve>& curves, double* log_loss = nullptr);
// A species file with `terms` appended as terms on the holding alone.
Result<std::string> with_hold_terms(const std::string& species_json, const std::vector<components::DeteriorationTerm>& terms);

struct ValidationResult {
    std::string measured_file;
    std::string species;                 // what the extension was fitted for
    MeasuredData data;
    AnalysisInput input;
    AnalysisResult analysis;
    std::vector<std::string> explanations; // per cause, same order
    std::string extended_species_json;   // empty when nothing was found
    std::vector<double> simulated_extended_gf; // the extended species through the simulation, per row
    std::optional<double> simulated_extended_rmse_gf;
    std::string resimulation_note;       // why it was skipped, when it was
    std::optional<FlowerSpread> spread;            // the flowers' own differences, after the model
    std::optional<OutcomeScores> baseline_outcome; // over rows whose outcome is stood or fell
    std::optional<OutcomeScores> extended_outcome;
    // Each row's predicted chance of falling (the mixture's share that fell), baseline and extended
    // species; empty when the data has no outcome column (extended: or it was not re-simulated).
    std::vector<double> baseline_fall_probability, extended_fall_probability;
    std::optional<OutcomeSearch> outcome_search; // with an outcome column: what it gets wrong about falls
    std::string outcome_note;                    // why there is no outcome search, when there is none
    std::vector<OtherMeasure> others; // every other measured quantity, before and after the extension
    std::vector<SpeciesCheck> by_species; // several species in the file: per species
    bool per_species = false;             // the shared extension was clearly worse for one: each has its own
};

// Where --write-species FILE puts species S's file when the data hold several: FILE's name with
// "-S" before its extension (ext.json -> ext-iris.json), S in an id's letters.
std::string species_output_path(const std::string& path, const std::string& species);

// The extended species' file with its extension applied to `applies_to` ("push" or "push_and_hold").
Result<std::string> extended_species_applied_to(const std::string& species_json, const std::string& applies_to);

Result<ValidationResult> run_validation(const std::string& measured_path, const ValidationOptions& options);

// The species file with its deterioration replaced by the fitted extension (terms appended when the
// species was already extended). `measured_file` is recorded in "fitted_from".
Result<std::string> extended_species_json(const std::string& species, const std::vector<components::DeteriorationTerm>& terms,
                                          const std::string& measured_file);

} // namespace ikebana::game
