#include "game/analysis/discrepancy_analysis.hpp"

#include "game/analysis/discrepancy_stages.hpp"
#include "systems/insertion/deterioration.hpp"

#include <algorithm>
#include <unordered_map>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <random>

#include <Eigen/Dense>

namespace ikebana::game {

namespace {

// The screening's table once the model is known: the causes, each with the shape it was fitted with,
// and every column's p-value given the final model.
std::vector<CovariateDiagnostic> given_model(std::vector<CovariateDiagnostic> diagnostics, const std::vector<discrepancy::Term>& causes,
                                             const discrepancy::Elimination& backward) {
    std::vector<double> given_model_p = backward.given_model_p;
    for (std::size_t k = 0; k < causes.size(); ++k) {
        const discrepancy::Term& t = causes[k];
        diagnostics[t.candidate].cause = true;
        // The screening's strongest single shape can differ from the one the cause was fitted with
        // (chosen by cross-validation, a peak only when it turns): the table says the cause's.
        diagnostics[t.candidate].best_shape = describe_shape(t.shape);
        given_model_p[t.candidate] = backward.kept_p[k];
    }
    for (std::size_t c = 0; c < diagnostics.size(); ++c) diagnostics[c].p_given_model = given_model_p[c];
    return diagnostics;
}

// The result: the baseline's figures beside the final fit's.
AnalysisResult result_of(const discrepancy::Analysis& a, discrepancy::FinalFit fit, std::vector<CovariateDiagnostic> diagnostics,
                         std::vector<std::string> log) {
    const std::size_t n = a.in.measured_gf.size();
    AnalysisResult result;
    result.n_trials = n;
    result.n_flowers = a.n_flowers;
    result.rows_as_groups = a.rows_as_groups;
    result.folds = a.folds;
    result.baseline_rmse_gf = discrepancy::rmse_gf(a.in, nullptr);
    result.baseline_cv_rmse_gf = result.baseline_rmse_gf; // the baseline fits nothing
    result.baseline_log_rmse = std::sqrt(a.r.squaredNorm() / static_cast<double>(n));
    result.discrepancy_found = fit.extended;
    result.calibration = fit.calibration;
    result.diagnostics = std::move(diagnostics);
    result.causes = std::move(fit.causes);
    result.interactions = std::move(fit.checks);
    result.extension = std::move(fit.extension);
    result.fitted_log_factor.assign(fit.fitted.data(), fit.fitted.data() + a.n);
    result.cv_log_factor.assign(fit.oof.data(), fit.oof.data() + a.n);
    result.extended_rmse_gf = fit.extended ? discrepancy::rmse_gf(a.in, &fit.fitted) : result.baseline_rmse_gf;
    result.extended_cv_rmse_gf = fit.extended ? discrepancy::rmse_gf(a.in, &fit.oof) : result.baseline_cv_rmse_gf;
    result.extended_log_rmse = std::sqrt((a.r - fit.fitted).squaredNorm() / static_cast<double>(n));
    result.gain = fit.extended && result.baseline_cv_rmse_gf > 0.0 ? 1.0 - result.extended_cv_rmse_gf / result.baseline_cv_rmse_gf : 0.0;
    result.log = std::move(log);
    return result;
}

// The stages in order (discrepancy_stages.hpp), each on what the ones before it found.
Result<AnalysisResult> run(const AnalysisInput& input, const AnalysisOptions& options) {
    if (auto checked = discrepancy::check_rows(input); !checked) return std::move(checked).error();
    const discrepancy::Analysis a(input, options);
    discrepancy::Screening screening = discrepancy::screen(a);
    const discrepancy::Selection forward = discrepancy::select_forward(a, screening.first);
    const discrepancy::Elimination backward = discrepancy::eliminate_backward(a, forward);
    discrepancy::Interactions interactions = discrepancy::add_interactions(a, backward.terms);
    std::vector<std::string> log = std::move(screening.log);
    for (const discrepancy::Log* stage : std::initializer_list<const discrepancy::Log*>{&forward.log, &backward.log, &interactions.log}) {
        log.insert(log.end(), stage->begin(), stage->end());
    }
    auto diagnostics = given_model(std::move(screening.diagnostics), interactions.causes, backward);
    discrepancy::FinalFit fit = discrepancy::fit_final(a, std::move(interactions), backward.kept_p, screening.calibration);
    return result_of(a, std::move(fit), std::move(diagnostics), std::move(log));
}

} // namespace

namespace {

// Screens the categorical columns too wide for a per-level factor (AnalysisOptions says when) and
// returns the input without them. A per-level factor would be a dense design column per level: 60,000
// rows of a 10,000-level lot number are 4.8 GB before a single permutation.
AnalysisInput screened_input(const AnalysisInput& input, const AnalysisOptions& options, std::vector<ScreenedColumn>& screened) {
    AnalysisInput kept;
    kept.observed = input.observed;
    kept.flower = input.flower;
    kept.measured_gf = input.measured_gf;
    kept.predicted_gf = input.predicted_gf;
    kept.covariates.constant = input.covariates.constant;
    const std::size_t n = input.measured_gf.size();
    std::vector<double> r(n);
    double mean = 0.0;
    for (std::size_t i = 0; i < n; ++i) mean += (r[i] = residual_of(input, i)) / static_cast<double>(n);
    double total = 0.0;
    for (const double v : r) total += (v - mean) * (v - mean);
    for (const auto& column : input.covariates.columns) {
        if (column.numeric || column.levels.size() < 2) {
            kept.covariates.columns.push_back(column);
            continue;
        }
        // Distinct flowers per level, and the level means: one pass over the rows, grouped.
        const std::size_t levels = column.levels.size();
        std::vector<std::pair<std::uint32_t, std::size_t>> level_flower; // (level, flower's index)
        std::unordered_map<std::string, std::size_t> flower_index;
        std::vector<double> sum(levels, 0.0);
        std::vector<std::size_t> count(levels, 0);
        for (std::size_t i = 0; i < n; ++i) {
            const auto [it, added] = flower_index.emplace(input.flower[i], flower_index.size());
            level_flower.emplace_back(column.level[i], it->second);
            sum[column.level[i]] += r[i] - mean;
            ++count[column.level[i]];
        }
        std::sort(level_flower.begin(), level_flower.end());
        const auto distinct = static_cast<double>(std::unique(level_flower.begin(), level_flower.end()) - level_flower.begin());
        const double flowers_per_level = distinct / static_cast<double>(levels);
        if (flowers_per_level >= options.min_flowers_per_level && levels <= options.max_levels) {
            kept.covariates.columns.push_back(column);
            continue;
        }
        ScreenedColumn s;
        s.covariate = column.name;
        s.levels = levels;
        s.flowers_per_level = flowers_per_level;
        double between = 0.0;
        for (std::size_t l = 0; l < levels; ++l) between += count[l] > 0 ? sum[l] * sum[l] / static_cast<double>(count[l]) : 0.0;
        s.between_level_share = total > 0.0 ? between / total : 0.0;
        s.chance_share = n > 1 ? static_cast<double>(levels - 1) / static_cast<double>(n - 1) : 0.0;
        char why[256];
        if (levels > options.max_levels) {
            std::snprintf(why, sizeof why, "%zu levels, more than the %zu a per-level effect is tested for (a lot, sample or gauge id, or a note)", levels,
                          options.max_levels);
        } else {
            std::snprintf(why, sizeof why, "its %zu levels are seen on %.1f flowers each on average: a per-level effect needs at least %.0f to be told from the flowers' own differences",
                          levels, flowers_per_level, options.min_flowers_per_level);
        }
        s.reason = why;
        screened.push_back(std::move(s));
    }
    return kept;
}

// The working memory the analysis will hold for `input`, in bytes, and the name of the column that
// needs most of it. A numeric shape is a column a row long (its basis, its rest off the model, a fold's
// copy); a categorical column is a factor: its levels' whitening (levels^2) and, once per analysis, a
// permutation batch off the model (64 columns) and one indicator column.
std::pair<std::size_t, std::string> working_memory(const AnalysisInput& input) {
    const std::size_t n = input.measured_gf.size();
    std::size_t bytes = 3 * 8 * n * sizeof(double); // the intercept, the residuals and the model's own
    bool any_factor = false;
    std::size_t widest = 0;
    std::string widest_name;
    for (const auto& column : input.covariates.columns) {
        std::size_t need = 0;
        if (column.numeric) {
            need = 3 * all_shapes_of(column).size() * n * sizeof(double);
        } else {
            const std::size_t levels = column.levels.size();
            need = 3 * levels * levels * sizeof(double);
            any_factor = true;
        }
        bytes += need;
        if (need > widest) {
            widest = need;
            widest_name = column.name;
        }
    }
    if (any_factor) bytes += (64 + 1) * n * sizeof(double);
    return {bytes, widest_name};
}

} // namespace

AnalysisInput input_rows(const AnalysisInput& in, const std::vector<std::size_t>& rows) {
    AnalysisInput kept;
    kept.observed = in.observed;
    kept.covariates.constant = in.covariates.constant;
    for (const auto& c : in.covariates.columns) {
        CovariateColumn k = c;
        k.values.clear();
        k.level.clear();
        kept.covariates.columns.push_back(std::move(k));
    }
    kept.flower.reserve(rows.size());
    for (std::size_t i : rows) {
        kept.flower.push_back(in.flower[i]);
        kept.measured_gf.push_back(in.measured_gf[i]);
        kept.predicted_gf.push_back(in.predicted_gf[i]);
        for (std::size_t c = 0; c < in.covariates.columns.size(); ++c) {
            const auto& from = in.covariates.columns[c];
            auto& to = kept.covariates.columns[c];
            if (from.numeric) to.values.push_back(from.values[i]);
            else to.level.push_back(from.level[i]);
        }
    }
    return kept;
}

namespace {

// The input without the rows in `out` (sorted).
AnalysisInput without_rows(const AnalysisInput& in, const std::vector<std::size_t>& out) {
    std::vector<std::size_t> rows;
    for (std::size_t i = 0, k = 0; i < in.measured_gf.size(); ++i) {
        if (k < out.size() && out[k] == i) ++k;
        else rows.push_back(i);
    }
    return input_rows(in, rows);
}

// The fitted extension's log factor at row i of the input, as the species model applies it.
double model_log_factor(const std::vector<components::DeteriorationTerm>& extension, const AnalysisInput& in, std::size_t i) {
    systems::insertion::Covariates covariates;
    double insertion = 1.0;
    for (const auto& c : in.covariates.columns) {
        if (c.numeric) covariates.numeric[c.name] = c.values[i];
        else covariates.category[c.name] = c.levels[c.level[i]];
        if (c.numeric && c.name == "insertion") insertion = c.values[i];
    }
    return std::log(systems::insertion::extension_factor(extension, static_cast<std::uint32_t>(std::max(1.0, insertion)), covariates));
}

// Each residual's distance from their median in robust standard deviations (1.4826 x the median
// absolute deviation): the one scale rows are set aside by and reported in.
std::vector<double> robust_z(const std::vector<double>& residual) {
    std::vector<double> sorted = residual;
    std::sort(sorted.begin(), sorted.end());
    const double median = sorted[sorted.size() / 2];
    std::vector<double> deviation;
    for (double r : residual) deviation.push_back(std::abs(r - median));
    std::nth_element(deviation.begin(), deviation.begin() + static_cast<std::ptrdiff_t>(deviation.size() / 2), deviation.end());
    const double sd = std::max(1.4826 * deviation[deviation.size() / 2], 1e-6); // no row is an outlier of exact data
    std::vector<double> z;
    for (double r : residual) z.push_back((r - median) / sd);
    return z;
}

// Numeric columns a row-set-aside left with nothing to test (one value, or no step threshold with rows on
// both sides) join the constant ones: a candidate needs a shape.
void drop_untestable(AnalysisInput& in) {
    auto& columns = in.covariates.columns;
    for (auto it = columns.begin(); it != columns.end();) {
        if (it->numeric && all_shapes_of(*it).empty()) {
            in.covariates.constant.push_back(it->name);
            it = columns.erase(it);
        } else {
            ++it;
        }
    }
}

// A random sample of whole flowers of about `target` rows (whole flowers: a few more; every row when
// there are fewer), in the file's order; `flowers` receives how many flowers it holds. The flowers
// holding each numeric column's lowest and highest value come first: a shape's origin and scale are
// taken from its column's range in the sample, and a row below it on every row made a log or a
// negative power infinite there.
std::vector<std::size_t> flower_sample(const AnalysisInput& in, std::size_t target, std::uint64_t seed, std::size_t& flowers) {
    const discrepancy::Groups groups = discrepancy::make_groups(in.flower, false);
    std::vector<bool> taken(groups.rows.size(), false);
    std::vector<std::size_t> order;
    for (const auto& column : in.covariates.columns) {
        if (!column.numeric || column.values.empty()) continue;
        const auto [lo, hi] = std::minmax_element(column.values.begin(), column.values.end());
        for (const auto at : {lo, hi}) {
            const std::size_t g = groups.of_row[static_cast<std::size_t>(at - column.values.begin())];
            if (!taken[g]) order.push_back(g);
            taken[g] = true;
        }
    }
    std::vector<std::size_t> rest;
    for (std::size_t g = 0; g < groups.rows.size(); ++g) {
        if (!taken[g]) rest.push_back(g);
    }
    std::mt19937_64 rng(seed ^ 0x5A4D'504CULL);
    std::shuffle(rest.begin(), rest.end(), rng);
    order.insert(order.end(), rest.begin(), rest.end());
    std::vector<std::size_t> rows;
    flowers = 0;
    for (std::size_t g : order) {
        if (rows.size() >= target) break;
        for (const Eigen::Index i : groups.rows[g]) rows.push_back(static_cast<std::size_t>(i));
        ++flowers;
    }
    std::sort(rows.begin(), rows.end());
    return rows;
}

// |z| beyond which a two-sided normal test has probability p.
double z_two_sided(double p) {
    double lo = 0.0, hi = 40.0;
    for (int k = 0; k < 100; ++k) {
        const double mid = 0.5 * (lo + hi);
        (std::erfc(mid / std::sqrt(2.0)) > p ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
}

// The slope of e on x as a z, its standard error from the flowers' sums (a flower's rows share its
// stem and its day: they are not independent, and a row-wise error would overstate the evidence).
double clustered_z(const Eigen::VectorXd& x, const Eigen::VectorXd& e, const discrepancy::Groups& groups) {
    const double sxx = x.squaredNorm();
    if (!(sxx > 0.0)) return 0.0;
    const double b = x.dot(e) / sxx;
    double v = 0.0;
    for (const auto& rows : groups.rows) {
        double s = 0.0;
        for (const Eigen::Index i : rows) s += x(i) * (e(i) - b * x(i));
        v += s * s;
    }
    return v > 0.0 ? b * sxx / std::sqrt(v) : 0.0;
}

// Every row's word on the numeric columns the sample's search left out of the model: a linear and a
// curved trend of each against the final residual.
SearchSample check_left_out(const discrepancy::Analysis& every, const Eigen::VectorXd& residual, const std::vector<bool>& in_model, double alpha) {
    SearchSample out;
    for (std::size_t c = 0; c < every.candidates.size(); ++c) {
        const CovariateColumn& column = every.column_of(c);
        if (!column.numeric || in_model[c]) continue;
        const Eigen::Index n = every.n;
        Eigen::VectorXd x(n);
        for (Eigen::Index i = 0; i < n; ++i) x(i) = column.values[static_cast<std::size_t>(i)];
        x.array() -= x.mean();
        Eigen::VectorXd q = x.array().square().matrix();
        q.array() -= q.mean();
        if (const double sxx = x.squaredNorm(); sxx > 0.0) q -= x * (x.dot(q) / sxx); // the curve apart from the line
        out.columns.push_back(column.name);
        out.z.push_back(std::max(std::abs(clustered_z(x, residual, every.groups)), std::abs(clustered_z(q, residual, every.groups))));
    }
    out.z_needed = z_two_sided(alpha / static_cast<double>(std::max<std::size_t>(1, 2 * out.columns.size())));
    return out;
}

// The search for causes on a sample of whole flowers, the final model on every row (`full` may lose a
// column the sample cannot test: a column must mean the same candidate in both).
Result<AnalysisResult> run_sampled(AnalysisInput& full, const AnalysisOptions& options, std::size_t target) {
    if (auto checked = discrepancy::check_rows(full); !checked) return std::move(checked).error();
    std::size_t flowers = 0;
    const std::vector<std::size_t> rows = flower_sample(full, target, options.seed, flowers);
    AnalysisInput sample = input_rows(full, rows);
    std::vector<std::string> untestable;
    for (std::size_t c = sample.covariates.columns.size(); c-- > 0;) {
        const auto& column = sample.covariates.columns[c];
        if (!column.numeric || !all_shapes_of(column).empty()) continue;
        // (Its extremes are in the sample, so this is a column with no step threshold there: said below.)
        untestable.push_back(column.name);
        full.covariates.constant.push_back(column.name);
        full.covariates.columns.erase(full.covariates.columns.begin() + static_cast<std::ptrdiff_t>(c));
        sample.covariates.columns.erase(sample.covariates.columns.begin() + static_cast<std::ptrdiff_t>(c));
    }
    discrepancy::Screening screening;
    discrepancy::Elimination backward;
    discrepancy::Interactions interactions;
    std::vector<std::string> log;
    {
        // The search, on the sample: its every shape's columns are freed before the every-row fit.
        const discrepancy::Analysis a(sample, options);
        screening = discrepancy::screen(a);
        const discrepancy::Selection forward = discrepancy::select_forward(a, screening.first);
        backward = discrepancy::eliminate_backward(a, forward);
        interactions = discrepancy::add_interactions(a, backward.terms);
        log = std::move(screening.log);
        for (const discrepancy::Log* stage : std::initializer_list<const discrepancy::Log*>{&forward.log, &backward.log, &interactions.log}) {
            log.insert(log.end(), stage->begin(), stage->end());
        }
    }
    const discrepancy::Analysis every(full, options, false);
    // The chosen terms at the shapes the search chose, on every row.
    auto on_every_row = [&](const discrepancy::Term& t) {
        discrepancy::Term u = every.make_term(t.candidate, t.shape);
        u.times = t.times;
        u.times_origin = t.times_origin;
        if (t.times) {
            const CovariateColumn& other = every.column_of(*t.times);
            for (Eigen::Index i = 0; i < every.n; ++i) u.basis(i, 0) *= other.values[static_cast<std::size_t>(i)] - t.times_origin;
        }
        return u;
    };
    std::vector<bool> in_model(every.candidates.size(), false);
    for (auto* terms : {&interactions.causes, &interactions.terms}) {
        for (auto& t : *terms) {
            in_model[t.candidate] = true;
            t = on_every_row(t);
        }
    }
    auto diagnostics = given_model(std::move(screening.diagnostics), interactions.causes, backward);
    discrepancy::FinalFit fit = discrepancy::fit_final(every, std::move(interactions), backward.kept_p, screening.calibration);
    SearchSample checked = check_left_out(every, every.r - fit.fitted, in_model, options.alpha);
    checked.rows = rows.size();
    checked.flowers = flowers;
    char line[400];
    std::snprintf(line, sizeof line,
                  "the search for causes ran on a random %zu of %zu flowers (%zu of %zu rows, about %zu: --search-rows); the model, its intervals and its "
                  "cross-validated gain are fitted on every row",
                  flowers, every.n_flowers, rows.size(), full.measured_gf.size(), options.search_rows);
    log.insert(log.begin(), line);
    for (const auto& name : untestable) log.insert(log.begin() + 1, "'" + name + "' has no shape to test in the sample (no threshold with rows on both sides): not tested");
    AnalysisResult result = result_of(every, std::move(fit), std::move(diagnostics), std::move(log));
    result.sample = std::move(checked);
    return result;
}

Result<AnalysisResult> analyse_rows(const AnalysisInput& input, const AnalysisOptions& options) {
    std::vector<ScreenedColumn> screened;
    AnalysisInput kept = screened_input(input, options, screened);
    drop_untestable(kept);
    const std::size_t n = kept.measured_gf.size();
    const auto [bytes, widest] = working_memory(kept);
    const bool sample = options.search_rows > 0 && (n > options.search_rows || bytes > options.memory_budget_bytes);
    // A sample: as many rows as the budget leaves once the fit on every row has its own (the
    // residuals, flowers, folds and the model's columns with their copies: about 32 numbers a row).
    const std::size_t every_row_bytes = sample ? 32 * n * sizeof(double) : 0;
    const std::size_t per_row = std::max<std::size_t>(1, bytes / std::max<std::size_t>(1, n));
    const std::size_t target = every_row_bytes < options.memory_budget_bytes
                                   ? std::min(options.search_rows, (options.memory_budget_bytes - every_row_bytes) / per_row)
                                   : 0;
    if (sample && every_row_bytes >= options.memory_budget_bytes) {
        return make_error(ErrorCode::invalid_argument, std::to_string(n) + " rows need " + std::to_string(every_row_bytes >> 10) +
                                                           " KiB for the fit on every row alone, more than the " + std::to_string(options.memory_budget_bytes >> 10) +
                                                           " KiB budget: raise --memory-mb or split the file by flower");
    }
    if ((!sample && bytes > options.memory_budget_bytes) || (sample && target < std::min<std::size_t>(1000, options.search_rows))) {
        return make_error(ErrorCode::invalid_argument,
                          "the covariates would need " + std::to_string(bytes >> 10) + " KiB of working memory, more than the " +
                              std::to_string(options.memory_budget_bytes >> 10) + " KiB budget" + (sample ? " even for a sample of 1,000 rows" : "") +
                              "; the widest is the column '" + widest + "': leave it out (--ignore " + widest + ") or split the file");
    }
    auto result = sample ? run_sampled(kept, options, target) : run(kept, options);
    if (result) result->screened = std::move(screened);
    return result;
}

} // namespace

Result<AnalysisResult> analyse_discrepancy(const AnalysisInput& input, const AnalysisOptions& options) {
    if (options.permutations < 19) return make_error(ErrorCode::invalid_argument, "at least 19 permutations are needed for p < 0.05");
    const std::size_t n = input.measured_gf.size();
    // An outcome is 0 or 1: no row of it is a gross error.
    if (options.outlier_z <= 0.0 || n < 20 || input.observed == Observed::outcome || input.predicted_gf.size() != n || input.flower.size() != n) return analyse_rows(input, options);
    for (const auto& c : input.covariates.columns) {
        if ((c.numeric ? c.values.size() : c.level.size()) != n) return analyse_rows(input, options); // refused there, naming the column
    }
    for (std::size_t i = 0; i < n; ++i) {
        const double m = input.measured_gf[i], p = input.predicted_gf[i];
        if (!(m > 0.0) || !(p > 0.0) || !std::isfinite(m) || !std::isfinite(p)) return analyse_rows(input, options); // refused there, naming the row
    }
    // Gross errors: first against the baseline, then against the model fitted without them (an effect
    // widens the baseline's spread and hides a moderate slip; a row the model explains comes back). At
    // most a tenth of the rows: beyond that it is not a few slips but the data.
    std::vector<double> model(n, 0.0);
    std::vector<std::size_t> aside;
    Result<AnalysisResult> result = make_error(ErrorCode::invalid_argument, "no analysis");
    for (int round = 0; round < 2; ++round) {
        std::vector<double> residual(n);
        for (std::size_t i = 0; i < n; ++i) residual[i] = std::log(input.measured_gf[i] / input.predicted_gf[i]) - model[i];
        const std::vector<double> z = robust_z(residual);
        std::vector<std::size_t> now;
        for (std::size_t i = 0; i < n; ++i) {
            if (std::abs(z[i]) > options.outlier_z) now.push_back(i);
        }
        if (now.size() > n / 10) {
            if (round == 0) now.clear();
            else break; // the model's second look finds too many: keep the first look's rows
        }
        if (round > 0 && now == aside) break;
        aside = std::move(now);
        result = aside.empty() ? analyse_rows(input, options) : analyse_rows(without_rows(input, aside), options);
        if (!result) return result;
        for (std::size_t i = 0; i < n; ++i) model[i] = result->extension.empty() ? 0.0 : model_log_factor(result->extension, input, i);
        if (aside.empty() && round > 0) break;
    }
    if (aside.empty()) return result;
    // Per-row answers for every row again; the set-aside rows get the model's value.
    AnalysisResult& a = *result;
    std::vector<double> fitted(n), cv(n);
    std::size_t k = 0;
    for (std::size_t i = 0; i < n; ++i) {
        if (std::binary_search(aside.begin(), aside.end(), i)) {
            fitted[i] = cv[i] = model[i];
            continue;
        }
        fitted[i] = a.fitted_log_factor[k];
        cv[i] = a.cv_log_factor[k];
        ++k;
    }
    a.fitted_log_factor = std::move(fitted);
    a.cv_log_factor = std::move(cv);
    // Their distance from the fitted model, on the scale they were set aside by.
    std::vector<double> residual(n);
    for (std::size_t i = 0; i < n; ++i) residual[i] = std::log(input.measured_gf[i] / input.predicted_gf[i]) - model[i];
    const std::vector<double> z = robust_z(residual);
    for (std::size_t i : aside) a.suspected.push_back({i, input.measured_gf[i], input.predicted_gf[i] * std::exp(model[i]), z[i]});
    a.n_trials = n;
    char line[160];
    std::snprintf(line, sizeof line, "%zu row(s) set aside as suspected gross errors (beyond %.0f robust standard deviations); the analysis ran on the other %zu",
                  aside.size(), options.outlier_z, n - aside.size());
    a.log.insert(a.log.begin(), line);
    return result;
}

} // namespace ikebana::game
