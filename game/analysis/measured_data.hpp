#pragma once
// Measured insertions (docs/measured-data.md): a CSV with a header; '#' lines are comments.
// Required: flower_id, insertion (integer >= 1), max_force_gf (> 0; a plan for `predict` may leave it out). Standard optional: species,
// angle_deg, depth_mm, pins, speed_mm_s, minutes_since_cut, hole_reuse (0/1), outcome (stood, fell,
// broke). Every other column is a candidate covariate, numeric or categorical.
#include <cstdint>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "engine/assets/csv_table.hpp"
#include "engine/core/result.hpp"
#include "systems/insertion/deterioration.hpp"

namespace ikebana::game {

struct MeasuredTrial {
    std::size_t line = 0;
    std::string flower_id;
    std::uint32_t insertion = 1;
    double max_force_gf = 0.0; // 0: not measured (a plan's row, MeasuredForce::optional)
    std::optional<std::string> species;
    std::optional<double> angle_deg;
    std::optional<double> depth_mm;
    std::optional<std::uint32_t> pins;
    std::optional<std::string> outcome;
    // The trial's other columns stay in the table (MeasuredData::covariates_of): a map per row was
    // most of the memory of a long file (500,000 rows: about 700 MB).
};

struct MeasuredData {
    assets::CsvTable table;
    std::vector<MeasuredTrial> trials;
    bool has_outcome = false;
    // Row i's covariates: every column but the identity, the measurement, the outcome and the species
    // (and the standard numeric ones); `only` (when given) keeps those names alone.
    systems::insertion::Covariates covariates_of(std::size_t i, const std::set<std::string>* only = nullptr) const;
};

// What a file must hold: `validate` compares with measurements, so every row needs max_force_gf;
// `predict` also takes a plan of trials not yet run (no column, or blank cells; max_force_gf is then 0).
enum class MeasuredForce { required, optional };

// Every problem is an error naming the file, the line and the column; nothing is returned half read.
Result<MeasuredData> read_measured_data(assets::CsvTable table, MeasuredForce force = MeasuredForce::required);
Result<MeasuredData> load_measured_data(const std::string& path, MeasuredForce force = MeasuredForce::required);

} // namespace ikebana::game
