#pragma once
// The forms an extension term may take, and their parameter grids. Numeric covariates get the generic
// monotone shapes (linear, logarithmic, saturating exponential, power, step with a threshold);
// categorical ones a factor per level against the most common level. The basis is computed by the same
// function the insertion system uses (systems/insertion/deterioration), so a fitted term means in the
// simulation exactly what it meant in the fit.
#include <string>
#include <vector>

#include <Eigen/Core>

#include "components/insertion.hpp"
#include "game/analysis/covariate_columns.hpp"

namespace ikebana::game {

struct TermShape {
    std::string form; // linear, log, saturating, power, step, category
    double scale = 0.0;
    double origin = 0.0;
};

std::vector<std::string> forms_for(const CovariateColumn& column);
// The parameter grid of one form, placed from the column's own range (never from its name).
std::vector<TermShape> shapes_of(const CovariateColumn& column, const std::string& form);
// Every shape of every form of the column.
std::vector<TermShape> all_shapes_of(const CovariateColumn& column);

// Rows x columns: one column for a numeric shape, one per non-reference level for a category.
Eigen::MatrixXd basis_of(const CovariateColumn& column, const TermShape& shape);
// The same basis for one row's values (for held-out rows): numeric x, or a level name.
double basis_value(const TermShape& shape, double x);

// The fitted coefficients as species terms (a category gives one term per non-reference level).
std::vector<components::DeteriorationTerm> terms_of(const CovariateColumn& column, const TermShape& shape,
                                                    const Eigen::VectorXd& coefficients);

// A short description: "saturating (length 2.1 from 1)", "step at 5.5", "category".
std::string describe_shape(const TermShape& shape);

} // namespace ikebana::game
