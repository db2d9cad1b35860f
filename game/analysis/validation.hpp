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
    std::optional<double> baseline_outcome_accuracy; // over rows whose outcome is stood or fell
    std::optional<double> extended_outcome_accuracy;
    std::size_t outcome_rows = 0;
};

Result<ValidationResult> run_validation(const std::string& measured_path, const ValidationOptions& options);

// The species file with its deterioration replaced by the fitted extension (terms appended when the
// species was already extended). `measured_file` is recorded in "fitted_from".
Result<std::string> extended_species_json(const std::string& species, const std::vector<components::DeteriorationTerm>& terms,
                                          const std::string& measured_file);

} // namespace ikebana::game
