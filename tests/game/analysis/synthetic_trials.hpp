#pragma once
// Synthetic measured data with a hidden effect, for tests and benchmarks of `ikebana validate`.
// Flowers x repeated insertions with standard and unknown covariates, including bystanders that are
// correlated with the planted cause; the "measured" force is the simulation's own prediction times the
// planted effect times log-normal noise (per trial and per flower). The analysis only ever sees the CSV.
#include <cstdint>
#include <string>
#include <vector>

#include "game/analysis/discrepancy_analysis.hpp"
#include "game/analysis/insertion_predictor.hpp"
#include "game/analysis/measured_data.hpp"

namespace ikebana::test {

// gross_outliers: a moderate real effect (humidity_pct, +0.4 %/%) with 3 % of the rows misread (the
// force x 0.35 or x 2.5: a slipped gauge, a misread scale).
// two_effects: +0.4 %/% on humidity_pct and -15 % from storage_days >= 6, at once.
// interaction: humidity's effect grows with storage days, +0.6 %/% x storage_days / 5 (none at day 0).
enum class PlantedEffect { none, unknown_numeric, category, insertion_count, step_threshold, saturating_decay, station, peaked_optimum, gross_outliers, two_effects, interaction };

struct PlantedTruth {
    std::string column;    // where the effect is planted (empty: none)
    std::string direction; // increases / decreases / nonmonotone
};

struct SyntheticOptions {
    PlantedEffect effect = PlantedEffect::none;
    std::uint64_t seed = 1;
    std::uint32_t flowers = 60;
    std::uint32_t insertions = 6;
    double trial_noise_sd = 0.05;  // ln scale: about 5 % per trial
    double flower_noise_sd = 0.03; // and 3 % between flowers
    std::uint32_t extra_covariates = 0; // more unknown noise columns (for the speed benchmark)
    // A 12-level `station` column (each flower measured at one of 12 stations; the effect `station` is
    // planted on station S07), and a `batch` column of this many levels, a lot number changing every
    // `rows_per_lot` rows (0: none): a bystander too wide to test level by level.
    bool station_column = false;
    std::uint32_t wide_levels = 0;
    std::uint32_t rows_per_lot = 1;
    // Columns humidity_copy_1.. : humidity_pct plus a little noise (sd 0.5 %), for a null with near-copies.
    std::uint32_t near_copies = 0;
    double effect_scale = 1.0; // the planted effect times this
};

struct SyntheticData {
    std::string csv;
    PlantedTruth truth;
    std::vector<double> true_log_factor; // per row: the planted effect (no noise)
    game::MeasuredData data;
    std::vector<double> simulated_gf;    // the simulation's prediction per row
    std::vector<std::size_t> gross_rows; // rows given a gross error (gross_outliers)
};

PlantedTruth truth_of(PlantedEffect effect);
const char* name_of(PlantedEffect effect);

// Simulates every distinct condition once through `predictor` (share it between calls: it caches).
SyntheticData make_synthetic_trials(const SyntheticOptions& options, game::InsertionPredictor& predictor);

// The analysis input for generated data (what validate builds from a file).
game::AnalysisInput analysis_input(const SyntheticData& data);

} // namespace ikebana::test
