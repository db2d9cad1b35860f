#pragma once
// The candidate covariates of measured data as columns the analysis can fit. Nothing here knows any
// column's meaning: a column is numeric when every non-empty cell is a number, categorical otherwise.
#include <cstdint>
#include <string>
#include <vector>

#include "engine/assets/csv_table.hpp"
#include "engine/core/result.hpp"

namespace ikebana::game {

struct CovariateColumn {
    std::string name;
    bool numeric = true;
    std::vector<double> values;        // numeric: per row; a missing cell takes the middle of its range
    std::vector<std::uint32_t> level;  // categorical: per row, an index into `levels`
    std::vector<std::string> levels;   // categorical: the most common first (the reference level)
    std::size_t missing = 0;           // empty cells (categorical ones are the level "(missing)")
    double fill_value = 0.0;           // numeric: what an empty cell takes (the middle of the range)
};

struct CovariateSet {
    std::vector<CovariateColumn> columns; // every candidate that varies, in the file's column order
    std::vector<std::string> constant;    // columns left out because they take one value only
};

// Every column but the flower id, the measurement, the outcome and what `predict` appends
// (predicted_*), less the `ignore` list (a name not in the file is an error naming it).
Result<CovariateSet> candidate_covariates(const assets::CsvTable& table, const std::vector<std::string>& ignore);

} // namespace ikebana::game
