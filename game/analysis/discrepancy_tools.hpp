#pragma once
// The working parts the discrepancy analysis' stages share (discrepancy_analysis.hpp says what the
// analysis does and why): the rows' residual grouped by flower and dealt into folds, the candidate
// covariates with every shape's basis, and the two tools every stage uses, the grouped permutation
// test (discrepancy_permutation_test.cpp) and grouped cross-validation (discrepancy_tools.cpp).
// Internal to game/analysis/: its stages (discrepancy_stages.hpp) are its only users.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "engine/core/result.hpp"
#include "game/analysis/discrepancy_analysis.hpp"
#include "game/analysis/grouped_design.hpp"
#include "game/analysis/term_shapes.hpp"

namespace ikebana::game::discrepancy {

using Rows = std::vector<Eigen::Index>;
using Log = std::vector<std::string>; // what a step decided, for the report

inline Eigen::Index idx(std::size_t i) { return static_cast<Eigen::Index>(i); }

// Rows grouped by flower (or one group per row when there are too few flowers to hold any out).
struct Groups {
    std::vector<Rows> rows;
    std::vector<std::size_t> of_row;
};

Groups make_groups(const std::vector<std::string>& flower, bool rows_as_groups);

// A candidate covariate with the raw basis of every shape of every form; a categorical one is a
// factor (its levels' means), with no columns at all.
struct Candidate {
    std::size_t column = 0;
    std::vector<TermShape> shapes;
    std::vector<Eigen::MatrixXd> bases; // per shape, numeric: a row-long column
    bool block = false;                 // categorical: the statistic is its levels' whole share
    Factor factor;
};

// A term kept in the model: one candidate at one shape.
struct Term {
    std::size_t candidate = 0;
    TermShape shape;
    Eigen::MatrixXd basis; // numeric; empty for a factor
    bool block = false;
    Factor factor;
    // An interaction: basis is the cause's times (column `times` - times_origin).
    std::optional<std::size_t> times;
    double times_origin = 0.0;
    Eigen::Index width() const { return block ? static_cast<Eigen::Index>(factor.levels) - 1 : basis.cols(); }
};

struct TestOutcome {
    std::vector<double> observed; // per candidate: share of the residual's sum of squares
    std::vector<double> p;
    std::vector<double> z;        // observed against the permutation distribution, in sds
    std::vector<std::size_t> best_shape;
    std::vector<double> adjusted; // family-wise: Westfall-Young step-down over the candidates tested
};

// The rows' measured and predicted forces as run() refuses them: fewer than 3, columns of different
// lengths, a force that is not positive, a covariate of another length.
Result<void> check_rows(const AnalysisInput& in);

// The input (checked by check_rows) as every stage sees it: the log residual, the flowers, the folds
// and the candidates; and the tests and fits on them.
struct Analysis {
    // bases = false: the candidates' shapes and factors without their row-long columns (a final fit on
    // every row of a long file whose search ran on a sample needs only the chosen terms').
    Analysis(const AnalysisInput& input, const AnalysisOptions& options, bool bases = true);

    TestOutcome test(const Eigen::VectorXd& residual, const GroupedDesign& design, const std::vector<std::size_t>& which, std::uint64_t stream,
                     const std::string& stage) const;
    // The same for candidates that need not be among candidates (a column's peaked shapes alone).
    TestOutcome test(const Eigen::VectorXd& residual, const GroupedDesign& design, const std::vector<const Candidate*>& which,
                     std::uint64_t stream, const std::string& stage) const;
    double level_p_value(const Eigen::VectorXd& residual, std::uint64_t stream) const;
    // The intercept (when asked for) and the numeric terms as columns, the categorical ones as factors.
    GroupedDesign design_of(const std::vector<Term>& terms, bool intercept) const;
    // A fit's coefficients laid out as the species' terms read them: the intercept, then each term's
    // (a factor's: a contrast per non-reference level).
    static Eigen::VectorXd coefficients_of(const std::vector<Term>& terms, const GroupedFit& fit);
    // The residual of r after the terms' fit over every row.
    Eigen::VectorXd residual_after(const std::vector<Term>& terms) const;
    // Grouped CV mean squared error of r by intercept + fixed terms (+ a free form whose shape is
    // chosen on each training fold); oof receives the held-out fits.
    double cv_mse(const std::vector<Term>& fixed, bool intercept, const Candidate* free, const std::string& form,
                  Eigen::VectorXd* oof = nullptr) const;
    TermShape best_shape_on_all(const std::vector<Term>& fixed, const Candidate& c, const std::string& form) const;
    // Each earlier numeric term's form and parameter (a step's threshold, a curve's scale) chosen
    // again given all the others: chosen before a second cause was in the model, it bent to carry
    // part of it.
    void refit_shapes(std::vector<Term>& terms, Log& log) const;
    // Candidate c at one shape, as a term of the model.
    Term make_term(std::size_t c, const TermShape& shape) const;
    const CovariateColumn& column_of(std::size_t candidate) const { return in.covariates.columns[candidate]; }
    // What the cross-validated error is, for the report's log.
    const char* loss_name() const { return in.observed == Observed::outcome ? "log-loss" : "MSE"; }

    const AnalysisInput& in;
    const AnalysisOptions& opt;
    Groups groups;
    std::size_t n_flowers = 0;
    bool rows_as_groups = false;  // fewer than 4 flowers: rows stand in for flowers
    std::uint32_t folds = 0;
    std::vector<int> fold_of_row;
    std::vector<Candidate> candidates;
    Eigen::VectorXd r; // ln(measured / predicted) per row
    Eigen::Index n = 0;
};

std::vector<double> holm(const std::vector<double>& p);
double quantile(std::vector<double> v, double q);
// RMSE in gf of the prediction times exp(log_factor) per row (none: the prediction itself).
double rmse_gf(const AnalysisInput& in, const Eigen::VectorXd* log_factor);

} // namespace ikebana::game::discrepancy
