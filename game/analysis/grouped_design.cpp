#include "game/analysis/grouped_design.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace ikebana::game {

namespace {

using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;

std::uint32_t level_at(const Factor& f, Index row) { return (*f.level)[static_cast<std::size_t>(row)]; }

// Several factors are demeaned in turn until nothing moves (alternating projections onto the
// complement of each factor's span, which converge to the complement of their joint span); one factor
// is exact after one sweep.
constexpr int max_sweeps = 2000;
constexpr double converged = 1e-13;

// Subtracts, column by column, the means of z's rows within each factor's levels; row i of z is the
// data's row rows[i].
void demean(const std::vector<Factor>& factors, const RowList& rows, Eigen::Ref<MatrixXd> z) {
    if (factors.empty() || z.cols() == 0) return;
    const double scale = std::max(z.cwiseAbs().maxCoeff(), 1e-300);
    std::vector<double> sum;
    std::vector<std::size_t> count;
    const int sweeps = factors.size() == 1 ? 1 : max_sweeps;
    for (int sweep = 0; sweep < sweeps; ++sweep) {
        double moved = 0.0;
        for (const Factor& f : factors) {
            count.assign(f.levels, 0);
            for (Index row : rows) ++count[level_at(f, row)];
            for (Index c = 0; c < z.cols(); ++c) {
                sum.assign(f.levels, 0.0);
                for (std::size_t i = 0; i < rows.size(); ++i) sum[level_at(f, rows[i])] += z(static_cast<Index>(i), c);
                for (std::size_t l = 0; l < f.levels; ++l) {
                    if (count[l] == 0) continue;
                    sum[l] /= static_cast<double>(count[l]);
                    moved = std::max(moved, std::abs(sum[l]));
                }
                for (std::size_t i = 0; i < rows.size(); ++i) z(static_cast<Index>(i), c) -= sum[level_at(f, rows[i])];
            }
        }
        if (moved <= converged * scale) break;
    }
}

// Columns that demeaning left at rounding noise (the intercept under a factor, a column constant
// within levels) are set to exactly zero: a rank-revealing QR judges rank relative to its largest
// pivot and would keep the noise when nothing else is left.
void zero_absorbed(const MatrixXd& before, MatrixXd& after) {
    for (Index c = 0; c < after.cols(); ++c) {
        if (after.col(c).norm() <= 1e-9 * std::max(before.col(c).norm(), 1e-300)) after.col(c).setZero();
    }
}

VectorXd pivoted_solve(const MatrixXd& x, const VectorXd& y) {
    if (x.cols() == 0) return VectorXd();
    Eigen::ColPivHouseholderQR<MatrixXd> qr(x);
    qr.setThreshold(1e-10);
    VectorXd beta = qr.solve(y);
    for (Index k = 0; k < beta.size(); ++k) {
        if (!std::isfinite(beta(k))) beta(k) = 0.0;
    }
    return beta;
}

} // namespace

RowList all_rows(Index n) {
    RowList rows(static_cast<std::size_t>(n));
    std::iota(rows.begin(), rows.end(), Index{0});
    return rows;
}

GroupedFit fit_grouped(const GroupedDesign& design, const VectorXd& y, const RowList& rows) {
    GroupedFit fit;
    const auto m = static_cast<Index>(rows.size());
    const MatrixXd x = design.dense(rows, Eigen::all);
    VectorXd target = y(rows);
    if (design.factors.empty()) {
        fit.dense = pivoted_solve(x, target);
        return fit;
    }
    MatrixXd xt = x;
    demean(design.factors, rows, xt);
    zero_absorbed(x, xt);
    VectorXd yt = target;
    demean(design.factors, rows, yt);
    fit.dense = xt.cols() ? pivoted_solve(xt, yt) : VectorXd();
    for (Index c = 0; c < xt.cols(); ++c) {
        if (xt.col(c).squaredNorm() == 0.0) fit.dense(c) = 0.0;
    }
    // What the dense columns leave, shared out among the factors by backfitting (one factor: its
    // levels' means, exactly).
    VectorXd left = x.cols() ? VectorXd(target - x * fit.dense) : target;
    for (const Factor& f : design.factors) fit.effects.push_back(VectorXd::Zero(static_cast<Index>(f.levels)));
    const double scale = std::max(left.cwiseAbs().maxCoeff(), 1e-300);
    const int sweeps = design.factors.size() == 1 ? 1 : max_sweeps;
    std::vector<double> sum;
    std::vector<std::size_t> count;
    for (int sweep = 0; sweep < sweeps; ++sweep) {
        double moved = 0.0;
        for (std::size_t k = 0; k < design.factors.size(); ++k) {
            const Factor& f = design.factors[k];
            VectorXd& effect = fit.effects[k];
            sum.assign(f.levels, 0.0);
            count.assign(f.levels, 0);
            for (Index i = 0; i < m; ++i) {
                const auto l = level_at(f, rows[static_cast<std::size_t>(i)]);
                sum[l] += left(i) + effect(static_cast<Index>(l));
                ++count[l];
            }
            for (std::size_t l = 0; l < f.levels; ++l) {
                if (count[l] == 0) continue;
                const double now = sum[l] / static_cast<double>(count[l]);
                moved = std::max(moved, std::abs(now - effect(static_cast<Index>(l))));
                sum[l] = now - effect(static_cast<Index>(l)); // the change
                effect(static_cast<Index>(l)) = now;
            }
            for (Index i = 0; i < m; ++i) left(i) -= sum[level_at(f, rows[static_cast<std::size_t>(i)])]; // 0 for an unseen level
        }
        if (moved <= converged * scale) break;
    }
    // Levels the fit never saw: the mean effect over its rows.
    for (std::size_t k = 0; k < design.factors.size(); ++k) {
        const Factor& f = design.factors[k];
        std::vector<bool> seen(f.levels, false);
        double mean = 0.0;
        for (Index row : rows) {
            const auto l = level_at(f, row);
            seen[l] = true;
            mean += fit.effects[k](static_cast<Index>(l));
        }
        mean /= std::max<double>(1.0, static_cast<double>(m));
        for (std::size_t l = 0; l < f.levels; ++l) {
            if (!seen[l]) fit.effects[k](static_cast<Index>(l)) = mean;
        }
    }
    return fit;
}

VectorXd predict_grouped(const GroupedDesign& design, const GroupedFit& fit, const RowList& rows) {
    VectorXd out = design.dense.cols() ? VectorXd(design.dense(rows, Eigen::all) * fit.dense) : VectorXd::Zero(static_cast<Index>(rows.size()));
    for (std::size_t k = 0; k < design.factors.size(); ++k) {
        for (std::size_t i = 0; i < rows.size(); ++i) out(static_cast<Index>(i)) += fit.effects[k](static_cast<Index>(level_at(design.factors[k], rows[i])));
    }
    return out;
}

VectorXd contrasts(const GroupedFit& fit, std::size_t factor) {
    const VectorXd& e = fit.effects[factor];
    return (e.tail(e.size() - 1).array() - e(0)).matrix();
}

double reference_intercept(const GroupedFit& fit) {
    double v = fit.dense.size() ? fit.dense(0) : 0.0;
    for (const auto& e : fit.effects) v += e(0);
    return v;
}

DesignComplement::DesignComplement(const GroupedDesign& design) : factors_(design.factors), rows_(all_rows(design.dense.rows())) {
    if (design.dense.cols() == 0) {
        q_ = MatrixXd(design.dense.rows(), 0);
        return;
    }
    MatrixXd x = design.dense;
    demean(factors_, rows_, x);
    zero_absorbed(design.dense, x);
    Eigen::ColPivHouseholderQR<MatrixXd> qr(x);
    qr.setThreshold(1e-10);
    const Index rank = x.squaredNorm() > 0.0 ? qr.rank() : 0;
    q_ = qr.householderQ() * MatrixXd::Identity(x.rows(), rank);
}

void DesignComplement::apply(Eigen::Ref<MatrixXd> v) const {
    if (!factors_.empty()) demean(factors_, rows_, v);
    if (q_.cols()) v -= q_ * (q_.transpose() * v);
}

// M = D' (I - P) D = U L U' (rank-revealing), T = L^-1/2 U'. Built a level at a time.
MatrixXd level_whitening(const Factor& f, const DesignComplement& model, Index n) {
    const auto levels = static_cast<Index>(f.levels);
    MatrixXd m(levels, levels);
    MatrixXd d(n, 1);
    for (Index l = 0; l < levels; ++l) {
        for (Index i = 0; i < n; ++i) d(i, 0) = (*f.level)[static_cast<std::size_t>(i)] == static_cast<std::uint32_t>(l) ? 1.0 : 0.0;
        model.apply(d);
        m.col(l) = sums_by_level(f, d).col(0);
    }
    const Eigen::SelfAdjointEigenSolver<MatrixXd> eig(0.5 * (m + m.transpose()));
    const double top = std::max(eig.eigenvalues().maxCoeff(), 0.0);
    std::vector<Index> keep;
    for (Index k = 0; k < levels; ++k) {
        if (eig.eigenvalues()(k) > 1e-9 * top && top > 0.0) keep.push_back(k);
    }
    MatrixXd t(static_cast<Index>(keep.size()), levels);
    for (std::size_t j = 0; j < keep.size(); ++j) {
        t.row(static_cast<Index>(j)) = eig.eigenvectors().col(keep[j]).transpose() / std::sqrt(eig.eigenvalues()(keep[j]));
    }
    return t;
}

MatrixXd sums_by_level(const Factor& factor, const Eigen::Ref<const MatrixXd>& v) {
    MatrixXd out = MatrixXd::Zero(static_cast<Index>(factor.levels), v.cols());
    for (Index c = 0; c < v.cols(); ++c) {
        for (Index i = 0; i < v.rows(); ++i) out(static_cast<Index>(level_at(factor, i)), c) += v(i, c);
    }
    return out;
}

} // namespace ikebana::game
