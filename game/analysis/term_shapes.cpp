#include "game/analysis/term_shapes.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>

#include "systems/insertion/deterioration.hpp"

namespace ikebana::game {

std::vector<std::string> forms_for(const CovariateColumn& column) {
    if (!column.numeric) return {"category"};
    const std::set<double> distinct(column.values.begin(), column.values.end());
    // Two values: every monotone shape is the same contrast; a step names it best (0/1 flags).
    if (distinct.size() <= 2) return {"step"};
    // An optimum (or a worst value) inside the range needs at least five values to be told from a bend.
    if (distinct.size() < 5) return {"linear", "log", "saturating", "power", "step"};
    return {"linear", "log", "saturating", "power", "step", "peaked"};
}

std::vector<TermShape> shapes_of(const CovariateColumn& column, const std::string& form) {
    if (form == "category") return {{"category", 0.0, 0.0}};
    const auto [lo_it, hi_it] = std::minmax_element(column.values.begin(), column.values.end());
    const double lo = *lo_it;
    const double range = *hi_it - lo;
    std::vector<TermShape> out;
    if (form == "linear") {
        out.push_back({"linear", 0.0, 0.0});
    } else if (form == "log") {
        // log(x - origin): the origin, always below the data, sets how sharply the curve bends there.
        for (double d : {0.05, 0.2, 1.0, 4.0}) out.push_back({"log", 0.0, lo - d * range});
    } else if (form == "saturating") {
        for (double f : {0.08, 0.15, 0.3, 0.5, 1.0}) out.push_back({"saturating", f * range, lo});
    } else if (form == "power") {
        for (double d : {0.2, 1.0}) {
            for (double q : {-1.0, -0.5, 0.5, 2.0, 3.0}) out.push_back({"power", q, lo - d * range});
        }
    } else if (form == "peaked") {
        // ((x - peak) / range)^2 with the peak at the 30th..70th percentile of the rows: a fitted
        // coefficient below 0 is an optimum there (the force highest at mid values), above 0 a trough.
        std::vector<double> sorted = column.values;
        std::sort(sorted.begin(), sorted.end());
        for (int k = 3; k <= 7; ++k) {
            const double at = sorted[static_cast<std::size_t>(std::lround(k / 10.0 * static_cast<double>(sorted.size() - 1)))];
            if (!out.empty() && out.back().origin == at) continue;
            out.push_back({"peaked", range, at});
        }
    } else if (form == "step") {
        // Thresholds between distinct values with at least 5 % of the rows on either side, at most 15.
        std::vector<double> sorted = column.values;
        std::sort(sorted.begin(), sorted.end());
        const std::size_t n = sorted.size();
        const std::size_t margin = std::max<std::size_t>(1, n / 20);
        std::vector<double> thresholds;
        for (std::size_t i = margin; i + margin <= n; ++i) {
            if (sorted[i] != sorted[i - 1]) thresholds.push_back(0.5 * (sorted[i] + sorted[i - 1]));
        }
        // A 0/1 flag whose rarer value has fewer rows than the margin still has its one threshold.
        if (thresholds.empty() && sorted.front() != sorted.back() && std::set<double>(sorted.begin(), sorted.end()).size() == 2) {
            thresholds.push_back(0.5 * (sorted.front() + sorted.back()));
        }
        if (thresholds.size() > 15) {
            std::vector<double> thinned;
            for (std::size_t k = 0; k < 15; ++k) thinned.push_back(thresholds[(k * (thresholds.size() - 1)) / 14]);
            thresholds = std::move(thinned);
        }
        for (double t : thresholds) out.push_back({"step", t, 0.0});
    }
    return out;
}

std::vector<TermShape> all_shapes_of(const CovariateColumn& column) {
    std::vector<TermShape> out;
    for (const auto& form : forms_for(column)) {
        auto shapes = shapes_of(column, form);
        out.insert(out.end(), shapes.begin(), shapes.end());
    }
    return out;
}

double basis_value(const TermShape& shape, double x) { return systems::insertion::term_basis(shape.form, x - shape.origin, shape.scale); }

Eigen::MatrixXd basis_of(const CovariateColumn& column, const TermShape& shape) {
    if (shape.form == "category") {
        const auto n = static_cast<Eigen::Index>(column.level.size());
        Eigen::MatrixXd b = Eigen::MatrixXd::Zero(n, static_cast<Eigen::Index>(column.levels.size()) - 1);
        for (Eigen::Index i = 0; i < n; ++i) {
            const auto l = column.level[static_cast<std::size_t>(i)];
            if (l > 0) b(i, static_cast<Eigen::Index>(l) - 1) = 1.0;
        }
        return b;
    }
    Eigen::MatrixXd b(static_cast<Eigen::Index>(column.values.size()), 1);
    for (std::size_t i = 0; i < column.values.size(); ++i) b(static_cast<Eigen::Index>(i), 0) = basis_value(shape, column.values[i]);
    return b;
}

std::vector<components::DeteriorationTerm> terms_of(const CovariateColumn& column, const TermShape& shape,
                                                    const Eigen::VectorXd& coefficients) {
    std::vector<components::DeteriorationTerm> out;
    if (shape.form == "category") {
        for (Eigen::Index k = 0; k < coefficients.size(); ++k) {
            out.push_back({.covariate = column.name, .form = "category", .coefficient = coefficients(k), .scale = 0.0,
                           .category = column.levels[static_cast<std::size_t>(k) + 1], .origin = 0.0, .range_low = 0.0, .range_high = 0.0, .times_covariate = {}, .times_origin = 0.0, .times_low = 0.0, .times_high = 0.0});
        }
        return out;
    }
    // The fitted curve holds a little beyond the data (a tenth of its range), no further.
    const auto [lo, hi] = std::minmax_element(column.values.begin(), column.values.end());
    const double margin = 0.1 * (*hi - *lo);
    out.push_back({.covariate = column.name, .form = shape.form, .coefficient = coefficients(0), .scale = shape.scale,
                   .category = {}, .origin = shape.origin, .range_low = *lo - margin, .range_high = *hi + margin, .times_covariate = {}, .times_origin = 0.0, .times_low = 0.0, .times_high = 0.0});
    return out;
}

std::string describe_shape(const TermShape& shape) {
    char text[128];
    char x[48];
    if (shape.origin == 0.0) std::snprintf(x, sizeof x, "x");
    else std::snprintf(x, sizeof x, "x %c %.4g", shape.origin > 0.0 ? '-' : '+', std::abs(shape.origin));
    if (shape.form == "log") std::snprintf(text, sizeof text, "log(%s)", x);
    else if (shape.form == "saturating") std::snprintf(text, sizeof text, "1 - exp(-(%s) / %.4g)", x, shape.scale);
    else if (shape.form == "power") std::snprintf(text, sizeof text, "(%s)^%.4g", x, shape.scale);
    else if (shape.form == "step") std::snprintf(text, sizeof text, "step at x >= %.4g", shape.scale);
    else if (shape.form == "peaked") std::snprintf(text, sizeof text, "((x - %.4g) / %.4g)^2, a peak or trough at %.4g", shape.origin, shape.scale, shape.origin);
    else if (shape.form == "linear") std::snprintf(text, sizeof text, "x");
    else std::snprintf(text, sizeof text, "a factor per level");
    return text;
}

} // namespace ikebana::game
