// The analysis' last stage: the extended model fitted on every row, as species terms, its causes with
// their effects and flower-bootstrap intervals, and its held-out fit.
#include "game/analysis/discrepancy_stages.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <random>

namespace ikebana::game::discrepancy {

using Eigen::Index;
using Eigen::VectorXd;

namespace {

// Relative change of the force across the covariate (numeric), or for the level that differs most
// from the row-weighted mean of the other levels (categorical: independent of the reference level).
double effect_of(const Cause& cause, const Eigen::VectorXd& coefficients, std::size_t* level = nullptr, std::optional<std::size_t> fixed = {}) {
    if (cause.shape.form == "category") {
        const std::size_t levels = cause.level_share.size();
        auto beta = [&](std::size_t l) { return l == 0 ? 0.0 : coefficients(static_cast<Index>(l) - 1); };
        auto deviation = [&](std::size_t l) {
            double s = 0.0, w = 0.0;
            for (std::size_t m = 0; m < levels; ++m) {
                if (m == l) continue;
                s += cause.level_share[m] * beta(m);
                w += cause.level_share[m];
            }
            return beta(l) - (w > 0.0 ? s / w : 0.0);
        };
        std::size_t best = fixed.value_or(0);
        if (!fixed) {
            for (std::size_t l = 1; l < levels; ++l) {
                const double d = std::abs(deviation(l)), b = std::abs(deviation(best));
                // Two levels differ from each other by the same amount: name the rarer, the one set apart.
                const bool tie = std::abs(d - b) <= 1e-9 * std::max(d, b);
                if ((!tie && d > b) || (tie && cause.level_share[l] < cause.level_share[best])) best = l;
            }
        }
        if (level) *level = best;
        return std::exp(deviation(best)) - 1.0;
    }
    const double b_low = basis_value(cause.shape, cause.x_low);
    const double b_high = basis_value(cause.shape, cause.x_high);
    // A peak or trough: from its top (or bottom) to the farther end of the range, where the basis is
    // largest (it is 0 at the peak).
    if (cause.shape.form == "peaked") return std::exp(coefficients(0) * std::max(b_low, b_high)) - 1.0;
    return std::exp(coefficients(0) * (b_high - b_low)) - 1.0;
}

// A numeric cause: the range its effect spans, and its curve across it.
void numeric_range(const CovariateColumn& column, Cause& cause) {
    const bool step = cause.shape.form == "step";
    cause.x_low = step ? *std::min_element(column.values.begin(), column.values.end()) : quantile(column.values, 0.05);
    cause.x_high = step ? *std::max_element(column.values.begin(), column.values.end()) : quantile(column.values, 0.95);
    // A count (insertions, days) is spoken of in its own values: the 1st to the 6th
    // insertion, not 1.25 to 5.75.
    if (std::all_of(column.values.begin(), column.values.end(), [](double x) { return x == std::round(x); })) {
        cause.x_low = std::round(cause.x_low);
        cause.x_high = std::round(cause.x_high);
    }
    for (int g = 0; g <= 40; ++g) {
        const double x = cause.x_low + (cause.x_high - cause.x_low) * g / 40.0;
        cause.curve_x.push_back(x);
        cause.curve_factor.push_back(std::exp(cause.coefficients(0) * basis_value(cause.shape, x)));
    }
}

// A categorical cause: its reference level, each level's share of the rows, and each level's factor.
void levels_of(const CovariateColumn& column, std::size_t rows, Cause& cause) {
    cause.reference = column.levels[0];
    cause.level_share.assign(column.levels.size(), 0.0);
    for (auto l : column.level) cause.level_share[l] += 1.0 / static_cast<double>(rows);
    cause.curve_x.push_back(0.0);
    cause.curve_factor.push_back(1.0);
    for (Index l = 0; l < cause.coefficients.size(); ++l) {
        cause.curve_x.push_back(static_cast<double>(l + 1));
        cause.curve_factor.push_back(std::exp(cause.coefficients(l)));
    }
}

// A kept term as a cause: its shape, coefficients, range or levels, effect and direction.
Cause cause_of(const Analysis& a, const Term& t, const VectorXd& coefficients) {
    const CovariateColumn& column = a.column_of(t.candidate);
    Cause cause;
    cause.covariate = column.name;
    cause.shape = t.shape;
    cause.coefficients = coefficients;
    if (column.numeric) numeric_range(column, cause);
    else levels_of(column, a.in.measured_gf.size(), cause);
    std::size_t level = 0;
    cause.effect_size = effect_of(cause, cause.coefficients, &level);
    if (!column.numeric) cause.category = column.levels[level];
    cause.direction = t.shape.form == "peaked" ? "nonmonotone" : cause.effect_size >= 0.0 ? "increases" : "decreases";
    return cause;
}

// The model's terms as one list and where its fit's coefficients lie.
struct Model {
    std::vector<Term> terms;      // the causes, then the interactions: the causes' coefficients come first in every fit below
    std::size_t causes_count = 0;
    GroupedDesign design;
    VectorXd beta;                // on every row, laid out by coefficients_of
    // The width of the causes' coefficients (after the intercept).
    std::size_t causes_width() const {
        std::size_t w = 0;
        for (std::size_t k = 0; k < causes_count; ++k) w += static_cast<std::size_t>(terms[k].width());
        return w;
    }
};

// An interaction: the cause's term times (the other column - its mean), held within the
// other column's range and a tenth beyond; and that column's own linear term.
void add_interaction_terms(const Analysis& a, const Model& m, FinalFit& out) {
    for (std::size_t k = m.causes_count; k < m.terms.size(); ++k) {
        const Term& t = m.terms[k];
        const CovariateColumn& column = a.column_of(t.candidate);
        auto term = terms_of(column, t.shape, m.beta.segment(1 + static_cast<Index>(m.causes_width()) + static_cast<Index>(k - m.causes_count), 1)).front();
        if (!t.times) {
            out.extension.push_back(term);
            continue;
        }
        const CovariateColumn& other = a.column_of(*t.times);
        const auto [lo, hi] = std::minmax_element(other.values.begin(), other.values.end());
        term.times_covariate = other.name;
        term.times_origin = t.times_origin;
        term.times_low = *lo - 0.1 * (*hi - *lo);
        term.times_high = *hi + 0.1 * (*hi - *lo);
        for (auto& i : out.checks) {
            if (i.kept && i.covariate == column.name && i.times == other.name) i.coefficient = term.coefficient;
        }
        out.extension.push_back(term);
    }
}

// Each cause's terms, its effect, and its importance: the share of the residual variance lost when
// it is dropped.
void add_causes(const Analysis& a, const Model& m, const std::vector<double>& kept_p, FinalFit& out) {
    Index at = 1;
    const double total = std::max((a.r.array() - a.r.mean()).matrix().squaredNorm(), 1e-300);
    const double sse_full = (a.r - out.fitted).squaredNorm();
    for (std::size_t k = 0; k < m.causes_count; ++k) {
        const Term& t = m.terms[k];
        Cause cause = cause_of(a, t, m.beta.segment(at, t.width()));
        at += t.width();
        const auto terms_here = terms_of(a.column_of(t.candidate), t.shape, cause.coefficients);
        out.extension.insert(out.extension.end(), terms_here.begin(), terms_here.end());
        cause.p_value = kept_p[k];
        std::vector<Term> others = m.terms;
        others.erase(others.begin() + static_cast<std::ptrdiff_t>(k));
        cause.importance = (a.residual_after(others).squaredNorm() - sse_full) / total;
        out.causes.push_back(std::move(cause));
    }
}

// Intervals: resample whole flowers, refit the same terms at the same shapes.
void add_intervals(const Analysis& a, const Model& m, FinalFit& out) {
    const RowList every_row = all_rows(a.n);
    std::vector<std::vector<double>> effects(m.causes_count);
    std::vector<double> levels;
    // A category: the same level as the point estimate, not whichever differs most here.
    std::vector<std::size_t> level_of(m.causes_count, 0);
    for (std::size_t k = 0; k < m.causes_count; ++k) effect_of(out.causes[k], out.causes[k].coefficients, &level_of[k]);
    std::mt19937_64 rng(a.opt.seed ^ 0xB007B007ULL);
    std::uniform_int_distribution<std::size_t> pick(0, a.groups.rows.size() - 1);
    for (std::uint32_t b = 0; b < a.opt.bootstrap; ++b) {
        // On every row of a long file these are the last tens of seconds: a terminal sees them.
        if (a.opt.progress && b % 8 == 0) a.opt.progress(bootstrap_stage, b, a.opt.bootstrap);
        RowList rows;
        for (std::size_t g = 0; g < a.groups.rows.size(); ++g) {
            const Rows& gr = a.groups.rows[pick(rng)];
            rows.insert(rows.end(), gr.begin(), gr.end());
        }
        const GroupedFit fit = fit_grouped(m.design, a.r, rows);
        const VectorXd bb = Analysis::coefficients_of(m.terms, fit);
        levels.push_back(std::exp(predict_grouped(m.design, fit, every_row).mean()));
        Index at = 1;
        for (std::size_t k = 0; k < m.causes_count; ++k) {
            const VectorXd coefficients = bb.segment(at, m.terms[k].width());
            at += m.terms[k].width();
            if (m.terms[k].block) {
                // A resample without one of its levels knows nothing of that level's effect (it enters
                // as the mean) and pulls the interval toward 0: such a resample says nothing here.
                const auto& of_row = *m.terms[k].factor.level;
                std::vector<bool> present(m.terms[k].factor.levels, false);
                for (Index i : rows) present[of_row[static_cast<std::size_t>(i)]] = true;
                if (std::find(present.begin(), present.end(), false) != present.end()) continue;
            }
            effects[k].push_back(effect_of(out.causes[k], coefficients, nullptr, level_of[k]));
        }
    }
    for (std::size_t k = 0; k < m.causes_count; ++k) {
        if (effects[k].empty()) effects[k].push_back(out.causes[k].effect_size); // no resample had the level
        out.causes[k].effect_low = quantile(effects[k], 0.025);
        out.causes[k].effect_high = quantile(effects[k], 0.975);
    }
    out.calibration.factor = std::exp(out.fitted.mean());
    out.calibration.low = quantile(levels, 0.025);
    out.calibration.high = quantile(levels, 0.975);
}

} // namespace

FinalFit fit_final(const Analysis& a, Interactions interactions, const std::vector<double>& kept_p, Calibration calibration) {
    FinalFit out;
    out.checks = std::move(interactions.checks);
    out.calibration = calibration;
    Model m;
    m.terms = std::move(interactions.causes);
    m.causes_count = m.terms.size();
    m.terms.insert(m.terms.end(), interactions.terms.begin(), interactions.terms.end());
    // The extended model: a level whenever anything is kept, and the terms.
    out.extended = !m.terms.empty() || calibration.significant;
    out.fitted = VectorXd::Zero(a.n);
    out.oof = VectorXd::Zero(a.n);
    if (!out.extended) return out;
    m.design = a.design_of(m.terms, true);
    m.beta = Analysis::coefficients_of(m.terms, fit_grouped(m.design, a.r, all_rows(a.n)));
    out.fitted = a.r - a.residual_after(m.terms);
    a.cv_mse(m.terms, true, nullptr, "", &out.oof);
    out.extension.push_back({.covariate = "level", .form = "constant", .coefficient = m.beta(0), .scale = 0.0, .category = {}, .origin = 0.0, .range_low = 0.0,
                             .range_high = 0.0, .times_covariate = {}, .times_origin = 0.0, .times_low = 0.0, .times_high = 0.0});
    add_interaction_terms(a, m, out);
    add_causes(a, m, kept_p, out);
    add_intervals(a, m, out);
    std::stable_sort(out.causes.begin(), out.causes.end(), [](const Cause& x, const Cause& y) { return x.importance > y.importance; });
    return out;
}

} // namespace ikebana::game::discrepancy
