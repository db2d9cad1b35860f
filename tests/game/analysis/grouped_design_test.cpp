// A factor held as its levels' means must answer exactly what a dense column per level answers: the
// reference below is the textbook design (intercept, numeric columns, a dummy per non-reference level)
// solved by pivoted QR.
#include <gtest/gtest.h>

#include <random>

#include "game/analysis/grouped_design.hpp"

using namespace ikebana::game;
using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;

namespace {

struct Data {
    Index n = 0;
    MatrixXd numeric;                         // n x 2
    std::vector<std::vector<std::uint32_t>> levels; // per factor
    std::vector<std::size_t> counts;
    VectorXd y;
};

// Unbalanced, crossed factors with real effects, two numeric columns, noise.
Data make_data(Index n, std::vector<std::size_t> counts, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> noise(0.0, 0.1);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    Data d;
    d.n = n;
    d.counts = counts;
    d.numeric.resize(n, 2);
    d.y.resize(n);
    d.levels.resize(counts.size());
    std::vector<VectorXd> effect;
    for (std::size_t L : counts) {
        VectorXd e(static_cast<Index>(L));
        for (Index l = 0; l < e.size(); ++l) e(l) = noise(rng) * 3.0;
        effect.push_back(e);
    }
    for (Index i = 0; i < n; ++i) {
        d.numeric(i, 0) = u(rng);
        d.numeric(i, 1) = u(rng) * u(rng);
        double v = 0.3 + 0.5 * d.numeric(i, 0) - 0.2 * d.numeric(i, 1) + noise(rng);
        for (std::size_t k = 0; k < counts.size(); ++k) {
            // Skewed: low levels are more common, so the design is unbalanced.
            const auto l = static_cast<std::uint32_t>(std::min<double>(static_cast<double>(counts[k] - 1), std::floor(u(rng) * u(rng) * static_cast<double>(counts[k]) * 1.3)));
            d.levels[k].push_back(l);
            v += effect[k](l);
        }
        d.y(i) = v;
    }
    return d;
}

GroupedDesign grouped(const Data& d) {
    GroupedDesign g;
    g.dense.resize(d.n, 3);
    g.dense.col(0).setOnes();
    g.dense.rightCols(2) = d.numeric;
    for (std::size_t k = 0; k < d.levels.size(); ++k) g.factors.push_back({&d.levels[k], d.counts[k]});
    return g;
}

MatrixXd dense_design(const Data& d) {
    Index cols = 3;
    for (std::size_t L : d.counts) cols += static_cast<Index>(L) - 1;
    MatrixXd x = MatrixXd::Zero(d.n, cols);
    x.col(0).setOnes();
    x.middleCols(1, 2) = d.numeric;
    Index at = 3;
    for (std::size_t k = 0; k < d.levels.size(); ++k) {
        for (Index i = 0; i < d.n; ++i) {
            const auto l = d.levels[k][static_cast<std::size_t>(i)];
            if (l > 0) x(i, at + l - 1) = 1.0;
        }
        at += static_cast<Index>(d.counts[k]) - 1;
    }
    return x;
}

VectorXd dense_fit(const MatrixXd& x, const VectorXd& y) {
    Eigen::ColPivHouseholderQR<MatrixXd> qr(x);
    qr.setThreshold(1e-10);
    return qr.solve(y);
}

} // namespace

TEST(GroupedDesign, OneFactorAsGroupMeansGivesTheDenseDesignsFitAndCoefficients) {
    const Data d = make_data(400, {12}, 1);
    const GroupedDesign g = grouped(d);
    const RowList rows = all_rows(d.n);
    const GroupedFit fit = fit_grouped(g, d.y, rows);
    const MatrixXd x = dense_design(d);
    const VectorXd beta = dense_fit(x, d.y);
    EXPECT_LT((predict_grouped(g, fit, rows) - x * beta).cwiseAbs().maxCoeff(), 1e-10);
    EXPECT_NEAR(reference_intercept(fit), beta(0), 1e-10);
    EXPECT_NEAR(fit.dense(1), beta(1), 1e-10);
    EXPECT_NEAR(fit.dense(2), beta(2), 1e-10);
    EXPECT_LT((contrasts(fit, 0) - beta.tail(11)).cwiseAbs().maxCoeff(), 1e-10);
}

TEST(GroupedDesign, TwoCrossedFactorsConvergeToTheDenseDesignsFit) {
    const Data d = make_data(600, {9, 15}, 2);
    const GroupedDesign g = grouped(d);
    const RowList rows = all_rows(d.n);
    const GroupedFit fit = fit_grouped(g, d.y, rows);
    const MatrixXd x = dense_design(d);
    const VectorXd beta = dense_fit(x, d.y);
    EXPECT_LT((predict_grouped(g, fit, rows) - x * beta).cwiseAbs().maxCoeff(), 1e-8);
    EXPECT_NEAR(fit.dense(1), beta(1), 1e-8);
    EXPECT_NEAR(reference_intercept(fit), beta(0), 1e-8);
    EXPECT_LT((contrasts(fit, 0) - beta.segment(3, 8)).cwiseAbs().maxCoeff(), 1e-8);
    EXPECT_LT((contrasts(fit, 1) - beta.segment(11, 14)).cwiseAbs().maxCoeff(), 1e-8);
}

// A bootstrap resample repeats rows; a fold leaves some out.
TEST(GroupedDesign, RepeatedAndMissingRowsCountAsOftenAsTheyAppear) {
    const Data d = make_data(300, {7}, 3);
    const GroupedDesign g = grouped(d);
    std::mt19937_64 rng(5);
    RowList rows;
    for (int k = 0; k < 300; ++k) rows.push_back(static_cast<Index>(rng() % 300));
    const GroupedFit fit = fit_grouped(g, d.y, rows);
    const MatrixXd x = dense_design(d)(rows, Eigen::all);
    const VectorXd y = d.y(rows);
    const VectorXd beta = dense_fit(x, y);
    EXPECT_LT((predict_grouped(g, fit, rows) - x * beta).cwiseAbs().maxCoeff(), 1e-10);
}

// The dense design would give an unseen level the reference level's value (its dummy's coefficient
// is free and pivoting sets it to 0), which depends on which level happens to come first; a level
// the fit never saw gets the mean effect of the rows it did see.
TEST(GroupedDesign, ALevelTheFitNeverSawGetsTheMeanEffectOfTheRowsItSaw) {
    const Data d = make_data(200, {5}, 4);
    const GroupedDesign g = grouped(d);
    RowList seen, unseen;
    for (Index i = 0; i < d.n; ++i) (d.levels[0][static_cast<std::size_t>(i)] == 3 ? unseen : seen).push_back(i);
    ASSERT_FALSE(unseen.empty());
    const GroupedFit fit = fit_grouped(g, d.y, seen);
    double mean = 0.0;
    for (Index i : seen) mean += fit.effects[0](d.levels[0][static_cast<std::size_t>(i)]);
    mean /= static_cast<double>(seen.size());
    EXPECT_NEAR(fit.effects[0](3), mean, 1e-12);
    EXPECT_TRUE(predict_grouped(g, fit, unseen).allFinite());
}

TEST(GroupedDesign, TheComplementAndALevelsWhiteningAreTheDenseProjections) {
    const Data d = make_data(500, {6, 20}, 6);
    // The model: intercept, numeric columns and the first factor; the candidate: the second factor.
    GroupedDesign model = grouped(d);
    model.factors.pop_back();
    const DesignComplement complement(model);
    MatrixXd z = MatrixXd::Zero(d.n, 3 + 5);
    z.leftCols(3) = model.dense;
    for (Index i = 0; i < d.n; ++i) {
        const auto l = d.levels[0][static_cast<std::size_t>(i)];
        if (l > 0) z(i, 3 + l - 1) = 1.0;
    }
    const MatrixXd p = z * (z.transpose() * z).completeOrthogonalDecomposition().pseudoInverse() * z.transpose();
    MatrixXd v = d.y;
    complement.apply(v);
    const VectorXd dense_off = d.y - p * d.y;
    EXPECT_LT((v.col(0) - dense_off).cwiseAbs().maxCoeff(), 1e-10);

    const Factor candidate{&d.levels[1], d.counts[1]};
    const MatrixXd t = level_whitening(candidate, complement, d.n);
    MatrixXd ind = MatrixXd::Zero(d.n, 20);
    for (Index i = 0; i < d.n; ++i) ind(i, d.levels[1][static_cast<std::size_t>(i)]) = 1.0;
    const MatrixXd w = ind - p * ind; // the candidate's columns off the model
    const MatrixXd pw = w * (w.transpose() * w).completeOrthogonalDecomposition().pseudoInverse() * w.transpose();
    const double dense_stat = (pw * dense_off).squaredNorm();
    const double grouped_stat = (t * sums_by_level(candidate, v)).squaredNorm();
    EXPECT_GT(dense_stat, 0.0);
    EXPECT_NEAR(grouped_stat, dense_stat, 1e-8 * dense_stat);
    // The candidate's span off the model has one dimension fewer than its levels (the intercept).
    EXPECT_EQ(t.rows(), 19);
}
