#pragma once
// Least squares with categorical factors held as group means, never as a dense design column per
// level (issue 19): a 200-level column over 60,000 rows is 96 MB as dummies and 1.6 KB as means.
//
// A design is dense columns (the intercept, numeric terms) plus factors. Fitting absorbs the factors:
// the dense columns and the response are demeaned within the factors' levels (exactly, in one pass,
// for one factor; by alternating projections for several), the dense coefficients come from the
// demeaned least squares (Frisch-Waugh-Lovell), and each factor's effects are then the group means of
// what is left. The fitted values are those of the dense design with a dummy per level: the same span,
// so the same projection.
#include <cstdint>
#include <vector>

#include <Eigen/Dense>

namespace ikebana::game {

struct Factor {
    const std::vector<std::uint32_t>* level = nullptr; // per row of the whole data, in [0, levels)
    std::size_t levels = 0;
};

struct GroupedDesign {
    Eigen::MatrixXd dense; // rows of the whole data x dense columns
    std::vector<Factor> factors;
};

struct GroupedFit {
    Eigen::VectorXd dense;                // a coefficient per dense column (0 for one the factors absorb)
    std::vector<Eigen::VectorXd> effects; // per factor, per level; a level the fit never saw gets its
                                          // fitted rows' mean effect (nothing is known about it)
};

using RowList = std::vector<Eigen::Index>;

RowList all_rows(Eigen::Index n);

// Least squares of y (indexed by the whole data's rows) on the design over `rows`; a row may repeat
// (a bootstrap resample) and counts as often as it appears. Column pivoting: a rank-deficient design
// still gives a finite answer.
GroupedFit fit_grouped(const GroupedDesign& design, const Eigen::VectorXd& y, const RowList& rows);

// The fit's values at `rows`.
Eigen::VectorXd predict_grouped(const GroupedDesign& design, const GroupedFit& fit, const RowList& rows);

// Factor k's effects against its first level, as a dummy per non-reference level would have them:
// effect[l] - effect[0] for l = 1 .. levels - 1.
Eigen::VectorXd contrasts(const GroupedFit& fit, std::size_t factor);

// Dense column 0's coefficient (the intercept) once every factor's first level is folded into it.
double reference_intercept(const GroupedFit& fit);

// v minus its projection on the design's span, over all rows (the permutation tests' residual maker).
class DesignComplement {
public:
    explicit DesignComplement(const GroupedDesign& design); // design.dense must have every row, even with no columns
    // Each column of v, in place.
    void apply(Eigen::Ref<Eigen::MatrixXd> v) const;
    bool identity() const { return q_.cols() == 0 && factors_.empty(); }

private:
    std::vector<Factor> factors_;
    RowList rows_;
    Eigen::MatrixXd q_; // orthonormal basis of the dense columns after demeaning within the factors
};

// Row sums of v by level: levels x v's columns.
Eigen::MatrixXd sums_by_level(const Factor& factor, const Eigen::Ref<const Eigen::MatrixXd>& v);

// A factor's levels off a model's span, as a whitening T of their sums: for any v off the span,
// |T * sums_by_level(v)|^2 is the squared norm of v's projection on the factor's indicator columns
// once they are taken off the span. Nothing a row long per level is held: levels^2 numbers in all
// (a permutation test's statistic for a factor is this, on each permuted residual).
Eigen::MatrixXd level_whitening(const Factor& factor, const DesignComplement& model, Eigen::Index rows);

} // namespace ikebana::game
