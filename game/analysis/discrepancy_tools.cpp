#include "game/analysis/discrepancy_tools.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <random>

namespace ikebana::game::discrepancy {

using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;

Groups make_groups(const std::vector<std::string>& flower, bool rows_as_groups) {
    Groups g;
    g.of_row.resize(flower.size());
    std::map<std::string, std::size_t> index;
    for (std::size_t i = 0; i < flower.size(); ++i) {
        const std::string key = rows_as_groups ? std::to_string(i) : flower[i];
        const auto [it, fresh] = index.emplace(key, g.rows.size());
        if (fresh) g.rows.emplace_back();
        g.rows[it->second].push_back(idx(i));
        g.of_row[i] = it->second;
    }
    return g;
}

} // namespace ikebana::game::discrepancy

namespace ikebana::game {

double held_out_loss(const AnalysisInput& in, std::size_t i, double model) {
    if (in.observed == Observed::outcome) {
        const double chance = std::clamp(in.predicted_gf[i] + model, 0.001, 0.999);
        return -(in.measured_gf[i] * std::log(chance) + (1.0 - in.measured_gf[i]) * std::log(1.0 - chance));
    }
    const double e = residual_of(in, i) - model;
    return e * e;
}

} // namespace ikebana::game

namespace ikebana::game::discrepancy {

Result<void> check_rows(const AnalysisInput& in) {
    const std::size_t n = in.measured_gf.size();
    if (n < 3) return make_error(ErrorCode::invalid_argument, "the analysis needs at least 3 trials, got " + std::to_string(n));
    if (in.predicted_gf.size() != n || in.flower.size() != n) {
        return make_error(ErrorCode::invalid_argument, "measured, predicted and flower columns differ in length");
    }
    for (std::size_t i = 0; in.observed == Observed::outcome && i < n; ++i) {
        if ((in.measured_gf[i] != 0.0 && in.measured_gf[i] != 1.0) || !(in.predicted_gf[i] >= 0.0 && in.predicted_gf[i] <= 1.0)) {
            return make_error(ErrorCode::invalid_argument, "row " + std::to_string(i + 1) + ": an outcome is 0 or 1 and its chance within [0, 1] (outcome " +
                                                               std::to_string(in.measured_gf[i]) + ", chance " + std::to_string(in.predicted_gf[i]) + ")");
        }
    }
    for (std::size_t i = 0; in.observed == Observed::force && i < n; ++i) {
        if (!(in.measured_gf[i] > 0.0) || !(in.predicted_gf[i] > 0.0) || !std::isfinite(in.measured_gf[i]) || !std::isfinite(in.predicted_gf[i])) {
            return make_error(ErrorCode::invalid_argument, "row " + std::to_string(i + 1) + ": measured and predicted forces must be positive (measured " +
                                                               std::to_string(in.measured_gf[i]) + ", predicted " + std::to_string(in.predicted_gf[i]) + ")");
        }
    }
    for (const auto& c : in.covariates.columns) {
        if ((c.numeric ? c.values.size() : c.level.size()) != n) {
            return make_error(ErrorCode::invalid_argument, "covariate '" + c.name + "' has a different number of rows");
        }
    }
    return Ok{};
}

namespace {

// Folds: whole flowers, dealt out in a seeded random order.
std::vector<int> deal_folds(const Groups& groups, std::size_t rows, std::uint32_t folds, std::uint64_t seed) {
    std::vector<std::size_t> order(groups.rows.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::mt19937_64 rng(seed);
    std::shuffle(order.begin(), order.end(), rng);
    std::vector<int> fold_of_row(rows, 0);
    for (std::size_t k = 0; k < order.size(); ++k) {
        for (Index i : groups.rows[order[k]]) fold_of_row[static_cast<std::size_t>(i)] = static_cast<int>(k % folds);
    }
    return fold_of_row;
}

std::vector<Candidate> candidates_of(const CovariateSet& covariates, bool bases) {
    std::vector<Candidate> candidates;
    for (std::size_t c = 0; c < covariates.columns.size(); ++c) {
        const auto& column = covariates.columns[c];
        Candidate cand;
        cand.column = c;
        cand.block = !column.numeric;
        cand.shapes = all_shapes_of(column);
        if (cand.block) cand.factor = {&column.level, column.levels.size()};
        else if (bases) for (const auto& s : cand.shapes) cand.bases.push_back(basis_of(column, s));
        candidates.push_back(std::move(cand));
    }
    return candidates;
}

} // namespace

Analysis::Analysis(const AnalysisInput& input, const AnalysisOptions& options, bool bases) : in(input), opt(options) {
    const std::size_t rows = in.measured_gf.size();
    n = idx(rows);
    r.resize(n);
    for (std::size_t i = 0; i < rows; ++i) r(idx(i)) = residual_of(in, i);
    groups = make_groups(in.flower, false);
    n_flowers = groups.rows.size();
    if (groups.rows.size() < 4) {
        rows_as_groups = true;
        groups = make_groups(in.flower, true);
    }
    folds = std::min<std::uint32_t>(std::max<std::uint32_t>(2, opt.folds), static_cast<std::uint32_t>(groups.rows.size()));
    fold_of_row = deal_folds(groups, rows, folds, opt.seed);
    candidates = candidates_of(in.covariates, bases);
}

GroupedDesign Analysis::design_of(const std::vector<Term>& terms, bool intercept) const {
    GroupedDesign d;
    Index cols = intercept ? 1 : 0;
    for (const auto& t : terms) cols += t.block ? 0 : t.basis.cols();
    d.dense.resize(n, cols);
    Index at = 0;
    if (intercept) d.dense.col(at++).setOnes();
    for (const auto& t : terms) {
        if (t.block) {
            d.factors.push_back(t.factor);
        } else {
            d.dense.middleCols(at, t.basis.cols()) = t.basis;
            at += t.basis.cols();
        }
    }
    return d;
}

VectorXd Analysis::coefficients_of(const std::vector<Term>& terms, const GroupedFit& fit) {
    Index width = 1;
    for (const auto& t : terms) width += t.width();
    VectorXd out(width);
    out(0) = reference_intercept(fit);
    Index at = 1, dense_at = 1;
    std::size_t factor = 0;
    for (const auto& t : terms) {
        if (t.block) {
            out.segment(at, t.width()) = contrasts(fit, factor++);
        } else {
            out.segment(at, t.width()) = fit.dense.segment(dense_at, t.width());
            dense_at += t.width();
        }
        at += t.width();
    }
    return out;
}

VectorXd Analysis::residual_after(const std::vector<Term>& terms) const {
    const GroupedDesign design = design_of(terms, true);
    const RowList rows = all_rows(n);
    return r - predict_grouped(design, fit_grouped(design, r, rows), rows);
}

double Analysis::cv_mse(const std::vector<Term>& fixed, bool intercept, const Candidate* free, const std::string& form, VectorXd* oof) const {
    const GroupedDesign base = design_of(fixed, intercept);
    std::vector<std::size_t> free_shapes;
    if (free) {
        for (std::size_t k = 0; k < free->shapes.size(); ++k) {
            if (free->shapes[k].form == form) free_shapes.push_back(k);
        }
        // A form with no shape here (a step with no threshold that leaves rows on both sides) is no
        // candidate: it must not win with the base model's error.
        if (free_shapes.empty()) return INFINITY;
    }
    // The base design with the free candidate at shape k.
    std::vector<GroupedDesign> with;
    for (std::size_t k : free_shapes) {
        GroupedDesign d;
        if (free->block) {
            d.dense = base.dense;
            d.factors = base.factors;
            d.factors.push_back(free->factor);
        } else {
            d.dense.resize(n, base.dense.cols() + free->bases[k].cols());
            d.dense << base.dense, free->bases[k];
            d.factors = base.factors;
        }
        with.push_back(std::move(d));
    }
    double sse = 0.0;
    if (oof) oof->setZero(n);
    for (int f = 0; f < static_cast<int>(folds); ++f) {
        RowList train, held;
        for (Index i = 0; i < n; ++i) (fold_of_row[static_cast<std::size_t>(i)] == f ? held : train).push_back(i);
        if (held.empty() || train.empty()) continue;
        const VectorXd y = r(train);
        VectorXd fit_held = VectorXd::Zero(static_cast<Index>(held.size()));
        if (free_shapes.empty()) {
            if (base.dense.cols() || !base.factors.empty()) fit_held = predict_grouped(base, fit_grouped(base, r, train), held);
        } else {
            double best = INFINITY;
            for (const GroupedDesign& d : with) {
                const GroupedFit fit = fit_grouped(d, r, train);
                const double train_sse = (y - predict_grouped(d, fit, train)).squaredNorm();
                if (train_sse < best) {
                    best = train_sse;
                    fit_held = predict_grouped(d, fit, held);
                }
            }
        }
        for (std::size_t k = 0; k < held.size(); ++k) sse += held_out_loss(in, static_cast<std::size_t>(held[k]), fit_held(static_cast<Index>(k)));
        if (oof) (*oof)(held) = fit_held;
    }
    return sse / static_cast<double>(n);
}

TermShape Analysis::best_shape_on_all(const std::vector<Term>& fixed, const Candidate& c, const std::string& form) const {
    if (c.block) return c.shapes[0]; // a factor has one shape
    const GroupedDesign base = design_of(fixed, true);
    const RowList rows = all_rows(n);
    double best = INFINITY;
    TermShape shape;
    for (std::size_t k = 0; k < c.shapes.size(); ++k) {
        if (c.shapes[k].form != form) continue;
        GroupedDesign d;
        d.dense.resize(n, base.dense.cols() + c.bases[k].cols());
        d.dense << base.dense, c.bases[k];
        d.factors = base.factors;
        const double sse = (r - predict_grouped(d, fit_grouped(d, r, rows), rows)).squaredNorm();
        if (sse < best) {
            best = sse;
            shape = c.shapes[k];
        }
    }
    return shape;
}

void Analysis::refit_shapes(std::vector<Term>& terms, Log& log) const {
    if (terms.size() < 2) return;
    for (std::size_t k = 0; k + 1 < terms.size(); ++k) {
        Term& t = terms[k];
        if (t.block) continue;
        std::vector<Term> others = terms;
        others.erase(others.begin() + static_cast<std::ptrdiff_t>(k));
        // Its form too, by the same cross-validation (a peak stays a peak: it passed its turn test).
        std::string form = t.shape.form;
        if (form != "peaked") {
            double best = INFINITY;
            for (const auto& f : forms_for(column_of(t.candidate))) {
                if (f == "peaked") continue;
                const double cv = cv_mse(others, true, &candidates[t.candidate], f);
                if (cv < best) {
                    best = cv;
                    form = f;
                }
            }
        }
        const TermShape shape = best_shape_on_all(others, candidates[t.candidate], form);
        if (shape.form == t.shape.form && shape.scale == t.shape.scale && shape.origin == t.shape.origin) continue;
        log.push_back("  re-fitted '" + column_of(t.candidate).name + "' given the others: " + describe_shape(t.shape) + " -> " + describe_shape(shape));
        t.shape = shape;
        t.basis = basis_of(column_of(t.candidate), shape);
    }
}

Term Analysis::make_term(std::size_t c, const TermShape& shape) const {
    const Candidate& cand = candidates[c];
    Term term;
    term.candidate = c;
    term.shape = shape;
    term.block = cand.block;
    term.factor = cand.factor;
    if (!term.block) term.basis = basis_of(column_of(c), term.shape);
    return term;
}

std::vector<double> holm(const std::vector<double>& p) {
    std::vector<std::size_t> order(p.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return p[a] < p[b]; });
    std::vector<double> adjusted(p.size(), 1.0);
    double running = 0.0;
    for (std::size_t k = 0; k < order.size(); ++k) {
        running = std::max(running, std::min(1.0, static_cast<double>(p.size() - k) * p[order[k]]));
        adjusted[order[k]] = running;
    }
    return adjusted;
}

double quantile(std::vector<double> v, double q) {
    if (v.empty()) return NAN;
    std::sort(v.begin(), v.end());
    const double at = q * static_cast<double>(v.size() - 1);
    const auto lo = static_cast<std::size_t>(std::floor(at));
    const std::size_t hi = std::min(lo + 1, v.size() - 1);
    return v[lo] + (at - static_cast<double>(lo)) * (v[hi] - v[lo]);
}

double rmse_gf(const AnalysisInput& in, const VectorXd* log_factor) {
    double s = 0.0;
    for (std::size_t i = 0; i < in.measured_gf.size(); ++i) {
        const double predicted = in.predicted_gf[i] * (log_factor ? std::exp((*log_factor)(idx(i))) : 1.0);
        s += (in.measured_gf[i] - predicted) * (in.measured_gf[i] - predicted);
    }
    return std::sqrt(s / static_cast<double>(in.measured_gf.size()));
}

} // namespace ikebana::game::discrepancy
