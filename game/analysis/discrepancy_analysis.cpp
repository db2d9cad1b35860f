#include "game/analysis/discrepancy_analysis.hpp"

#include "game/analysis/grouped_design.hpp"
#include "systems/insertion/deterioration.hpp"

#include <algorithm>
#include <unordered_map>
#include <cmath>
#include <cstdio>
#include <map>
#include <numeric>
#include <optional>
#include <random>

#include <Eigen/Dense>

namespace ikebana::game {

namespace {

using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;
using Rows = std::vector<Index>;

Index idx(std::size_t i) { return static_cast<Index>(i); }

// Rows grouped by flower (or one group per row when there are too few flowers to hold any out).
struct Groups {
    std::vector<Rows> rows;
    std::vector<std::size_t> of_row;
};

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

// A candidate covariate with the raw basis of every shape of every form; a categorical one is a
// factor (its levels' means), with no columns at all.
struct Candidate {
    std::size_t column = 0;
    std::vector<TermShape> shapes;
    std::vector<MatrixXd> bases; // per shape, numeric: a row-long column
    bool block = false;          // categorical: the statistic is its levels' whole share
    Factor factor;
};

// A term kept in the model: one candidate at one shape.
struct Term {
    std::size_t candidate = 0;
    TermShape shape;
    MatrixXd basis; // numeric; empty for a factor
    bool block = false;
    Factor factor;
    // An interaction: basis is the cause's times (column `times` - times_origin).
    std::optional<std::size_t> times;
    double times_origin = 0.0;
    Index width() const { return block ? static_cast<Index>(factor.levels) - 1 : basis.cols(); }
};

struct TestOutcome {
    std::vector<double> observed; // per candidate: share of the residual's sum of squares
    std::vector<double> p;
    std::vector<double> z;        // observed against the permutation distribution, in sds
    std::vector<std::size_t> best_shape;
    std::vector<double> adjusted; // family-wise: Westfall-Young step-down over the candidates tested
};

// -ln Q(k, x): the upper tail of a gamma of shape k (unit scale) beyond x, in nats; 0 for x <= 0.
// Series below k + 1, Lentz's continued fraction above (accurate far into the tail, where it matters).
double gamma_tail_score(double x, double k) {
    if (!(x > 0.0) || !(k > 0.0)) return 0.0;
    const double log_front = -x + k * std::log(x) - std::lgamma(k);
    if (x < k + 1.0) {
        double term = 1.0 / k, sum = term;
        for (int n = 1; n < 10000 && std::abs(term) > 1e-16 * std::abs(sum); ++n) {
            term *= x / (k + n);
            sum += term;
        }
        const double lower = std::exp(log_front) * sum; // P(k, x)
        return -std::log1p(-std::min(lower, 1.0 - 1e-16));
    }
    constexpr double tiny = 1e-300;
    double b = x + 1.0 - k, c = 1.0 / tiny, d = 1.0 / b, h = d;
    for (int i = 1; i < 10000; ++i) {
        const double an = -i * (i - k);
        b += 2.0;
        d = an * d + b;
        if (std::abs(d) < tiny) d = tiny;
        c = b + an / c;
        if (std::abs(c) < tiny) c = tiny;
        d = 1.0 / d;
        const double step = d * c;
        h *= step;
        if (std::abs(step - 1.0) < 1e-15) break;
    }
    return -(log_front + std::log(h));
}

class ResidualPermuter {
public:
    explicit ResidualPermuter(const Groups& groups) : groups_(groups) {}

    // One permutation of e: flower means among flowers, deviations within each flower.
    void permute(const VectorXd& e, std::mt19937_64& rng, float* out) {
        const std::size_t g = groups_.rows.size();
        means_.resize(g);
        for (std::size_t k = 0; k < g; ++k) {
            double s = 0.0;
            for (Index i : groups_.rows[k]) s += e(i);
            means_[k] = s / static_cast<double>(groups_.rows[k].size());
        }
        order_.resize(g);
        std::iota(order_.begin(), order_.end(), std::size_t{0});
        std::shuffle(order_.begin(), order_.end(), rng);
        for (std::size_t k = 0; k < g; ++k) {
            const Rows& rows = groups_.rows[k];
            within_.assign(rows.begin(), rows.end());
            std::shuffle(within_.begin(), within_.end(), rng);
            for (std::size_t j = 0; j < rows.size(); ++j) {
                out[rows[j]] = static_cast<float>(means_[order_[k]] + e(within_[j]) - means_[k]);
            }
        }
    }

private:
    const Groups& groups_;
    std::vector<double> means_;
    std::vector<std::size_t> order_;
    Rows within_;
};

// The columns of b off the model's span, normalised; a column that lies in the span (collinear with
// accepted terms) becomes zero.
MatrixXd orthonormal_rest(const MatrixXd& b, const DesignComplement& model) {
    MatrixXd w = b;
    model.apply(w);
    for (Index k = 0; k < w.cols(); ++k) {
        const double before = b.col(k).norm();
        const double norm = w.col(k).norm();
        if (norm <= 1e-8 * std::max(before, 1e-300)) w.col(k).setZero();
        else w.col(k) /= norm;
    }
    return w;
}

class Analysis {
public:
    Analysis(const AnalysisInput& input, const AnalysisOptions& options) : in_(input), opt_(options) {}
    Result<AnalysisResult> run();

private:
    TestOutcome test(const VectorXd& residual, const GroupedDesign& design, const std::vector<std::size_t>& which,
                     std::uint64_t stream, const std::string& stage);
    // The same for candidates that need not be among candidates_ (a column's peaked shapes alone).
    TestOutcome test(const VectorXd& residual, const GroupedDesign& design, const std::vector<const Candidate*>& which,
                     std::uint64_t stream, const std::string& stage);
    double level_p_value(const VectorXd& residual, std::uint64_t stream) const;
    // The intercept (when asked for) and the numeric terms as columns, the categorical ones as factors.
    GroupedDesign design_of(const std::vector<Term>& terms, bool intercept) const;
    // A fit's coefficients laid out as the species' terms read them: the intercept, then each term's
    // (a factor's: a contrast per non-reference level).
    static VectorXd coefficients_of(const std::vector<Term>& terms, const GroupedFit& fit);
    // The residual of r_ after the terms' fit over every row.
    VectorXd residual_after(const std::vector<Term>& terms) const;
    // Grouped CV mean squared error of r by intercept + fixed terms (+ a free form whose shape is
    // chosen on each training fold); oof receives the held-out fits.
    double cv_mse(const std::vector<Term>& fixed, bool intercept, const Candidate* free, const std::string& form,
                  VectorXd* oof = nullptr) const;
    TermShape best_shape_on_all(const std::vector<Term>& fixed, const Candidate& c, const std::string& form) const;
    // Each earlier numeric term's form and parameter (a step's threshold, a curve's scale) chosen
    // again given all the others: chosen before a second cause was in the model, it bent to carry
    // part of it.
    void refit_shapes(std::vector<Term>& terms);
    void report(const std::string& line) {
        result_.log.push_back(line);
    }

    const AnalysisInput& in_;
    const AnalysisOptions& opt_;
    AnalysisResult result_;
    Groups groups_;
    std::vector<int> fold_of_row_;
    std::vector<Candidate> candidates_;
    VectorXd r_;
    Index n_ = 0;
};

TestOutcome Analysis::test(const VectorXd& residual, const GroupedDesign& design, const std::vector<std::size_t>& which,
                           std::uint64_t stream, const std::string& stage) {
    std::vector<const Candidate*> candidates;
    for (std::size_t c : which) candidates.push_back(&candidates_[c]);
    return test(residual, design, candidates, stream, stage);
}

TestOutcome Analysis::test(const VectorXd& residual, const GroupedDesign& design, const std::vector<const Candidate*>& which,
                           std::uint64_t stream, const std::string& stage) {
    const DesignComplement model(design);
    VectorXd e = residual;
    model.apply(e);
    const double total = std::max(e.squaredNorm(), 1e-300);
    // Every numeric candidate's shapes side by side, orthonormal to the model: a statistic is then a
    // dot product. A categorical candidate's is its whitened level sums (factor_whitening).
    struct Span {
        Index begin, end;
        bool block;
        std::vector<std::size_t> shape_of_column;
        MatrixXd whitening; // block
        const Factor* factor = nullptr;
    };
    std::vector<MatrixXd> parts;
    std::vector<Span> spans;
    Index cols = 0;
    bool any_block = false;
    for (const Candidate* candidate : which) {
        const Candidate& cand = *candidate;
        Span s{cols, cols, cand.block, {}, {}, nullptr};
        if (cand.block) {
            s.whitening = level_whitening(cand.factor, model, n_);
            s.factor = &cand.factor;
            any_block = true;
        } else {
            for (std::size_t k = 0; k < cand.bases.size(); ++k) {
                MatrixXd w = orthonormal_rest(cand.bases[k], model);
                for (Index j = 0; j < w.cols(); ++j) s.shape_of_column.push_back(k);
                cols += w.cols();
                parts.push_back(std::move(w));
            }
        }
        s.end = cols;
        spans.push_back(std::move(s));
    }
    Eigen::MatrixXf w(n_, cols);
    {
        Index at = 0;
        for (const auto& p : parts) {
            w.middleCols(at, p.cols()) = p.cast<float>();
            at += p.cols();
        }
    }
    // g: the numeric columns' dot products; off: the vectors themselves off the model (for factors).
    auto statistic = [&](const Span& s, const auto& g, const MatrixXd& off, Index column_of_perm, std::size_t* best) {
        double stat = 0.0;
        if (s.block) {
            if (s.whitening.rows() == 0) return 0.0;
            const VectorXd sums = sums_by_level(*s.factor, off.col(column_of_perm));
            return (s.whitening * sums).squaredNorm();
        }
        for (Index j = s.begin; j < s.end; ++j) {
            const double v = static_cast<double>(g(j, column_of_perm)) * static_cast<double>(g(j, column_of_perm));
            if (v > stat) {
                stat = v;
                if (best) *best = s.shape_of_column[static_cast<std::size_t>(j - s.begin)];
            }
        }
        return stat;
    };
    TestOutcome out;
    const Eigen::VectorXf ef = e.cast<float>();
    const Eigen::MatrixXf g0 = w.transpose() * ef;
    const MatrixXd e_off = e; // already off the model
    std::vector<std::size_t> exceed(which.size(), 0);
    std::vector<double> sum(which.size(), 0.0), sum_sq(which.size(), 0.0);
    std::vector<double> permuted(static_cast<std::size_t>(opt_.permutations) * which.size()); // [b * C + c]
    for (std::size_t c = 0; c < which.size(); ++c) {
        std::size_t best = 0;
        out.observed.push_back(statistic(spans[c], g0, e_off, 0, &best) / total);
        out.best_shape.push_back(best);
    }
    std::mt19937_64 rng(opt_.seed * 0x9E3779B97F4A7C15ULL + stream);
    ResidualPermuter permuter(groups_);
    const std::uint32_t b_total = opt_.permutations;
    constexpr std::uint32_t batch = 64;
    Eigen::MatrixXf perm(n_, batch);
    MatrixXd perm_off; // the batch off the model, when a factor is tested
    for (std::uint32_t done = 0; done < b_total;) {
        const std::uint32_t now = std::min(batch, b_total - done);
        for (std::uint32_t k = 0; k < now; ++k) permuter.permute(e, rng, perm.col(k).data());
        const Eigen::MatrixXf g = w.transpose() * perm.leftCols(now);
        if (any_block) {
            perm_off = perm.leftCols(now).cast<double>();
            model.apply(perm_off);
        }
        for (std::uint32_t k = 0; k < now; ++k) {
            for (std::size_t c = 0; c < which.size(); ++c) {
                const double s = statistic(spans[c], g, perm_off, static_cast<Index>(k), nullptr) / total;
                permuted[(done + k) * which.size() + c] = s;
                sum[c] += s;
                sum_sq[c] += s * s;
                if (s >= out.observed[c] * (1.0 - 1e-6)) ++exceed[c];
            }
        }
        done += now;
        if (opt_.progress) opt_.progress(stage, done, b_total);
    }
    for (std::size_t c = 0; c < which.size(); ++c) {
        out.p.push_back((1.0 + static_cast<double>(exceed[c])) / (1.0 + b_total));
        const double mean = sum[c] / std::max(1u, b_total);
        const double sd = std::sqrt(std::max(sum_sq[c] / std::max(1u, b_total) - mean * mean, 1e-300));
        out.z.push_back((out.observed[c] - mean) / sd);
    }
    // Westfall-Young step-down maxT: the permutation counterpart of Holm that keeps the dependence
    // between candidates, so 1000 permutations can reach p = 0.001 for a whole family (Holm would need
    // 1000 x the family size). maxT is valid for any increasing transform of each column's statistic
    // applied alike to the observed and the permuted values; it is powerful only when the transformed
    // columns have alike tails. Mean/sd standardising does not give that: a 0/1 column's share is
    // chi-square-like with a long tail, a 12-flower column's max over shapes is not, and with 12 flowers
    // a real trend at z = 4.2 lost to the 0/1 columns' chance maxima (named in 2 of 40 seeds). So each
    // statistic becomes -ln of its upper tail under a gamma matched to its column's permutation mean
    // and variance: every column's null is then about Exp(1).
    const std::size_t m = which.size();
    std::vector<double> shape_k(m), scale_theta(m);
    // A column whose permuted statistics hardly vary (or whose match is not finite) is scored by its
    // rank among them instead: -ln of its permutation p-value.
    std::vector<std::vector<double>> by_rank(m);
    for (std::size_t c = 0; c < m; ++c) {
        const double mean = sum[c] / std::max(1u, b_total);
        double var = 0.0; // two passes: E[s^2] - mean^2 cancels when they are nearly equal
        for (std::uint32_t b = 0; b < b_total; ++b) var += (permuted[b * m + c] - mean) * (permuted[b * m + c] - mean);
        var /= std::max(1u, b_total);
        shape_k[c] = mean > 0.0 && var > 0.0 ? mean * mean / var : 0.0;
        scale_theta[c] = mean > 0.0 && var > 0.0 ? var / mean : 0.0;
        if (!(var > 1e-12 * mean * mean) || !std::isfinite(shape_k[c]) || shape_k[c] > 1e6) {
            for (std::uint32_t b = 0; b < b_total; ++b) by_rank[c].push_back(permuted[b * m + c]);
            std::sort(by_rank[c].begin(), by_rank[c].end());
        }
    }
    auto score = [&](std::size_t c, double x) {
        if (!by_rank[c].empty()) {
            const auto above = static_cast<double>(by_rank[c].end() - std::lower_bound(by_rank[c].begin(), by_rank[c].end(), x * (1.0 - 1e-9)));
            return -std::log((1.0 + above) / (1.0 + static_cast<double>(b_total)));
        }
        const double t = gamma_tail_score(x / scale_theta[c], shape_k[c]);
        return std::isfinite(t) ? t : 0.0;
    };
    std::vector<double> observed_score(m);
    for (std::size_t c = 0; c < m; ++c) observed_score[c] = score(c, out.observed[c]);
    std::vector<std::size_t> order(m);
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return observed_score[a] > observed_score[b]; });
    std::vector<std::size_t> count(m, 0);
    for (std::uint32_t b = 0; b < b_total; ++b) {
        // Successive maxima from the least significant up.
        double running = -INFINITY;
        for (std::size_t j = m; j-- > 0;) {
            const std::size_t c = order[j];
            running = std::max(running, score(c, permuted[b * m + c]));
            if (running >= observed_score[c] * (1.0 - 1e-9)) ++count[j];
        }
    }
    out.adjusted.assign(m, 1.0);
    double previous = 0.0;
    for (std::size_t j = 0; j < m; ++j) {
        const double p = std::max(previous, (1.0 + static_cast<double>(count[j])) / (1.0 + b_total));
        out.adjusted[order[j]] = std::max(p, out.p[order[j]]);
        previous = out.adjusted[order[j]];
    }
    return out;
}

// The overall level: |mean residual| against sign flips of whole flowers.
double Analysis::level_p_value(const VectorXd& residual, std::uint64_t stream) const {
    std::vector<double> sums;
    for (const auto& rows : groups_.rows) {
        double s = 0.0;
        for (Index i : rows) s += residual(i);
        sums.push_back(s);
    }
    const double observed = std::abs(std::accumulate(sums.begin(), sums.end(), 0.0));
    std::mt19937_64 rng(opt_.seed * 0x9E3779B97F4A7C15ULL + stream);
    std::size_t exceed = 0;
    for (std::uint32_t b = 0; b < opt_.permutations; ++b) {
        double s = 0.0;
        for (double v : sums) s += (rng() & 1U) ? v : -v;
        if (std::abs(s) >= observed * (1.0 - 1e-9)) ++exceed;
    }
    return (1.0 + static_cast<double>(exceed)) / (1.0 + opt_.permutations);
}

GroupedDesign Analysis::design_of(const std::vector<Term>& terms, bool intercept) const {
    GroupedDesign d;
    Index cols = intercept ? 1 : 0;
    for (const auto& t : terms) cols += t.block ? 0 : t.basis.cols();
    d.dense.resize(n_, cols);
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
    const RowList rows = all_rows(n_);
    return r_ - predict_grouped(design, fit_grouped(design, r_, rows), rows);
}

double Analysis::cv_mse(const std::vector<Term>& fixed, bool intercept, const Candidate* free, const std::string& form,
                        VectorXd* oof) const {
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
            d.dense.resize(n_, base.dense.cols() + free->bases[k].cols());
            d.dense << base.dense, free->bases[k];
            d.factors = base.factors;
        }
        with.push_back(std::move(d));
    }
    double sse = 0.0;
    if (oof) oof->setZero(n_);
    const int folds = static_cast<int>(result_.folds);
    for (int f = 0; f < folds; ++f) {
        RowList train, held;
        for (Index i = 0; i < n_; ++i) (fold_of_row_[static_cast<std::size_t>(i)] == f ? held : train).push_back(i);
        if (held.empty() || train.empty()) continue;
        const VectorXd y = r_(train);
        VectorXd fit_held = VectorXd::Zero(static_cast<Index>(held.size()));
        if (free_shapes.empty()) {
            if (base.dense.cols() || !base.factors.empty()) fit_held = predict_grouped(base, fit_grouped(base, r_, train), held);
        } else {
            double best = INFINITY;
            for (const GroupedDesign& d : with) {
                const GroupedFit fit = fit_grouped(d, r_, train);
                const double train_sse = (y - predict_grouped(d, fit, train)).squaredNorm();
                if (train_sse < best) {
                    best = train_sse;
                    fit_held = predict_grouped(d, fit, held);
                }
            }
        }
        const VectorXd err = r_(held) - fit_held;
        sse += err.squaredNorm();
        if (oof) (*oof)(held) = fit_held;
    }
    return sse / static_cast<double>(n_);
}

TermShape Analysis::best_shape_on_all(const std::vector<Term>& fixed, const Candidate& c, const std::string& form) const {
    if (c.block) return c.shapes[0]; // a factor has one shape
    const GroupedDesign base = design_of(fixed, true);
    const RowList rows = all_rows(n_);
    double best = INFINITY;
    TermShape shape;
    for (std::size_t k = 0; k < c.shapes.size(); ++k) {
        if (c.shapes[k].form != form) continue;
        GroupedDesign d;
        d.dense.resize(n_, base.dense.cols() + c.bases[k].cols());
        d.dense << base.dense, c.bases[k];
        d.factors = base.factors;
        const double sse = (r_ - predict_grouped(d, fit_grouped(d, r_, rows), rows)).squaredNorm();
        if (sse < best) {
            best = sse;
            shape = c.shapes[k];
        }
    }
    return shape;
}

void Analysis::refit_shapes(std::vector<Term>& terms) {
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
            for (const auto& f : forms_for(in_.covariates.columns[t.candidate])) {
                if (f == "peaked") continue;
                const double cv = cv_mse(others, true, &candidates_[t.candidate], f);
                if (cv < best) {
                    best = cv;
                    form = f;
                }
            }
        }
        const TermShape shape = best_shape_on_all(others, candidates_[t.candidate], form);
        if (shape.form == t.shape.form && shape.scale == t.shape.scale && shape.origin == t.shape.origin) continue;
        report("  re-fitted '" + in_.covariates.columns[t.candidate].name + "' given the others: " + describe_shape(t.shape) + " -> " + describe_shape(shape));
        t.shape = shape;
        t.basis = basis_of(in_.covariates.columns[t.candidate], shape);
    }
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

std::vector<ResidualBin> bins_of(const CovariateColumn& c, const VectorXd& r) {
    std::vector<std::vector<Index>> members;
    std::vector<std::string> labels;
    if (!c.numeric) {
        members.resize(c.levels.size());
        labels = c.levels;
        for (std::size_t i = 0; i < c.level.size(); ++i) members[c.level[i]].push_back(idx(i));
    } else {
        std::vector<double> distinct = c.values;
        std::sort(distinct.begin(), distinct.end());
        distinct.erase(std::unique(distinct.begin(), distinct.end()), distinct.end());
        char text[96];
        if (distinct.size() <= 10) {
            members.resize(distinct.size());
            for (double v : distinct) {
                std::snprintf(text, sizeof text, "%.4g", v);
                labels.emplace_back(text);
            }
            for (std::size_t i = 0; i < c.values.size(); ++i) {
                const auto at = std::lower_bound(distinct.begin(), distinct.end(), c.values[i]) - distinct.begin();
                members[static_cast<std::size_t>(at)].push_back(idx(i));
            }
        } else {
            // Deciles of the rows (ties kept together).
            std::vector<double> cuts;
            for (int k = 1; k < 10; ++k) cuts.push_back(quantile(c.values, k / 10.0));
            cuts.erase(std::unique(cuts.begin(), cuts.end()), cuts.end());
            members.resize(cuts.size() + 1);
            std::vector<double> lo(members.size(), INFINITY), hi(members.size(), -INFINITY);
            for (std::size_t i = 0; i < c.values.size(); ++i) {
                const auto at = static_cast<std::size_t>(std::upper_bound(cuts.begin(), cuts.end(), c.values[i]) - cuts.begin());
                members[at].push_back(idx(i));
                lo[at] = std::min(lo[at], c.values[i]);
                hi[at] = std::max(hi[at], c.values[i]);
            }
            for (std::size_t k = 0; k < members.size(); ++k) {
                std::snprintf(text, sizeof text, "%.4g-%.4g", lo[k], hi[k]);
                labels.emplace_back(text);
            }
        }
    }
    std::vector<ResidualBin> out;
    for (std::size_t k = 0; k < members.size(); ++k) {
        if (members[k].empty()) continue;
        ResidualBin b;
        b.label = labels[k];
        b.n = members[k].size();
        double s = 0.0, s2 = 0.0, x = 0.0;
        for (Index i : members[k]) {
            s += r(i);
            s2 += r(i) * r(i);
            if (c.numeric) x += c.values[static_cast<std::size_t>(i)];
        }
        const double n = static_cast<double>(b.n);
        const double mean = s / n;
        const double sem = b.n > 1 ? std::sqrt(std::max(0.0, (s2 - n * mean * mean) / (n - 1)) / n) : 0.0;
        b.x = c.numeric ? x / n : static_cast<double>(k);
        b.factor = std::exp(mean);
        b.low = std::exp(mean - 2 * sem);
        b.high = std::exp(mean + 2 * sem);
        out.push_back(b);
    }
    return out;
}

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

Result<AnalysisResult> Analysis::run() {
    const std::size_t n = in_.measured_gf.size();
    if (n < 3) return make_error(ErrorCode::invalid_argument, "the analysis needs at least 3 trials, got " + std::to_string(n));
    if (in_.predicted_gf.size() != n || in_.flower.size() != n) {
        return make_error(ErrorCode::invalid_argument, "measured, predicted and flower columns differ in length");
    }
    n_ = idx(n);
    r_.resize(n_);
    for (std::size_t i = 0; i < n; ++i) {
        if (!(in_.measured_gf[i] > 0.0) || !(in_.predicted_gf[i] > 0.0) || !std::isfinite(in_.measured_gf[i]) ||
            !std::isfinite(in_.predicted_gf[i])) {
            return make_error(ErrorCode::invalid_argument, "row " + std::to_string(i + 1) + ": measured and predicted forces must be positive (measured " +
                                                               std::to_string(in_.measured_gf[i]) + ", predicted " + std::to_string(in_.predicted_gf[i]) + ")");
        }
        r_(idx(i)) = std::log(in_.measured_gf[i] / in_.predicted_gf[i]);
    }
    for (const auto& c : in_.covariates.columns) {
        if ((c.numeric ? c.values.size() : c.level.size()) != n) {
            return make_error(ErrorCode::invalid_argument, "covariate '" + c.name + "' has a different number of rows");
        }
    }
    result_.n_trials = n;
    groups_ = make_groups(in_.flower, false);
    result_.n_flowers = groups_.rows.size();
    if (groups_.rows.size() < 4) {
        result_.rows_as_groups = true;
        groups_ = make_groups(in_.flower, true);
    }
    // Folds: whole flowers, dealt out in a seeded random order.
    result_.folds = std::min<std::uint32_t>(std::max<std::uint32_t>(2, opt_.folds), static_cast<std::uint32_t>(groups_.rows.size()));
    {
        std::vector<std::size_t> order(groups_.rows.size());
        std::iota(order.begin(), order.end(), std::size_t{0});
        std::mt19937_64 rng(opt_.seed);
        std::shuffle(order.begin(), order.end(), rng);
        fold_of_row_.assign(n, 0);
        for (std::size_t k = 0; k < order.size(); ++k) {
            for (Index i : groups_.rows[order[k]]) fold_of_row_[static_cast<std::size_t>(i)] = static_cast<int>(k % result_.folds);
        }
    }
    for (std::size_t c = 0; c < in_.covariates.columns.size(); ++c) {
        const auto& column = in_.covariates.columns[c];
        Candidate cand;
        cand.column = c;
        cand.block = !column.numeric;
        cand.shapes = all_shapes_of(column);
        if (cand.block) cand.factor = {&column.level, column.levels.size()};
        else for (const auto& s : cand.shapes) cand.bases.push_back(basis_of(column, s));
        candidates_.push_back(std::move(cand));
    }

    result_.baseline_rmse_gf = rmse_gf(in_, nullptr);
    result_.baseline_cv_rmse_gf = result_.baseline_rmse_gf; // the baseline fits nothing
    result_.baseline_log_rmse = std::sqrt(r_.squaredNorm() / static_cast<double>(n));

    // Step 1: every covariate against the baseline residual, and the overall level.
    std::vector<std::size_t> all(candidates_.size());
    std::iota(all.begin(), all.end(), std::size_t{0});
    const double level_p = level_p_value(r_, 0);
    GroupedDesign intercept_only;
    intercept_only.dense = MatrixXd::Ones(n_, 1);
    TestOutcome first = test(r_, intercept_only, all, 1, "testing every covariate");
    const std::vector<double>& first_adjusted = first.adjusted;
    for (std::size_t c = 0; c < candidates_.size(); ++c) {
        const auto& column = in_.covariates.columns[c];
        CovariateDiagnostic d;
        d.covariate = column.name;
        d.numeric = column.numeric;
        d.bins = bins_of(column, r_);
        d.strength = first.observed[c];
        d.best_shape = describe_shape(candidates_[c].shapes[first.best_shape[c]]);
        d.p_value = first.p[c];
        d.p_adjusted = first_adjusted[c];
        d.blank = column.missing;
        d.blank_value = column.fill_value;
        result_.diagnostics.push_back(std::move(d));
    }
    // The level is a family of its own: is the simulation's scale off at all?
    result_.calibration.p_value = level_p;
    const double cv_none = cv_mse({}, false, nullptr, "");
    const double cv_level = cv_mse({}, true, nullptr, "");
    result_.calibration.significant = level_p <= opt_.alpha && cv_level < cv_none;
    {
        char line[200];
        std::snprintf(line, sizeof line, "overall level: measured/predicted = %.3f, p = %.4g, CV MSE %.5f -> %.5f with a level: %s",
                      std::exp(r_.mean()), level_p, cv_none, cv_level, result_.calibration.significant ? "kept" : "not kept");
        report(line);
    }

    // Forward selection.
    std::vector<Term> terms;
    std::vector<std::size_t> remaining = all;
    std::vector<double> given_model_p(candidates_.size(), 1.0);
    bool tested_final_model = false;
    for (std::uint32_t step = 0; step < opt_.max_terms && !remaining.empty(); ++step) {
        TestOutcome t;
        std::vector<double> adjusted;
        if (step == 0) {
            t = first;
        } else {
            t = test(residual_after(terms), design_of(terms, true), remaining, 2 + step, "step " + std::to_string(step + 1) + ": given " + std::to_string(terms.size()) + " term(s)");
        }
        adjusted = t.adjusted;
        for (std::size_t k = 0; k < remaining.size(); ++k) given_model_p[remaining[k]] = adjusted[k];
        tested_final_model = true;
        std::vector<std::size_t> significant;
        for (std::size_t k = 0; k < remaining.size(); ++k) {
            if (adjusted[k] <= opt_.alpha) significant.push_back(k);
        }
        std::sort(significant.begin(), significant.end(), [&](std::size_t a, std::size_t b) { return t.z[a] > t.z[b]; });
        const double cv_now = cv_mse(terms, true, nullptr, "");
        bool accepted = false;
        for (std::size_t k : significant) {
            const std::size_t c = remaining[k];
            const Candidate& cand = candidates_[c];
            std::string best_form;
            double best_cv = INFINITY;
            std::string forms_text;
            std::string best_monotone;
            double best_monotone_cv = INFINITY;
            for (const auto& form : forms_for(in_.covariates.columns[c])) {
                const double cv = cv_mse(terms, true, &cand, form);
                char part[64];
                std::snprintf(part, sizeof part, "%s%s %.5f", forms_text.empty() ? "" : ", ", form.c_str(), cv);
                forms_text += part;
                if (cv < best_cv) {
                    best_cv = cv;
                    best_form = form;
                }
                if (form != "peaked" && cv < best_monotone_cv) {
                    best_monotone_cv = cv;
                    best_monotone = form;
                }
            }
            // A peak or trough must be shown to turn, not just fit a little better: a fast saturating
            // decay is fitted about as well by a trough near its flat end, whose rise past the vertex no
            // data shows. So the peaked shapes are tested, with permutations as every candidate is, on
            // what the best monotone form leaves; without a significant turn the form stays monotone.
            if (best_form == "peaked" && !best_monotone.empty()) {
                std::vector<Term> with_monotone = terms;
                Term mono;
                mono.candidate = c;
                mono.shape = best_shape_on_all(terms, cand, best_monotone);
                mono.basis = basis_of(in_.covariates.columns[c], mono.shape);
                with_monotone.push_back(std::move(mono));
                Candidate peaks;
                peaks.column = c;
                for (std::size_t s = 0; s < cand.shapes.size(); ++s) {
                    if (cand.shapes[s].form != "peaked") continue;
                    peaks.shapes.push_back(cand.shapes[s]);
                    peaks.bases.push_back(cand.bases[s]);
                }
                const TestOutcome turn = test(residual_after(with_monotone), design_of(with_monotone, true), std::vector<const Candidate*>{&peaks},
                                              500 + step, "does '" + in_.covariates.columns[c].name + "' turn?");
                char part[96];
                std::snprintf(part, sizeof part, "; a turn beyond %s: p = %.4g", best_monotone.c_str(), turn.p[0]);
                forms_text += part;
                if (turn.p[0] > opt_.alpha) {
                    best_form = best_monotone;
                    best_cv = best_monotone_cv;
                }
            }
            char line[512];
            std::snprintf(line, sizeof line, "step %u: '%s' p = %.4g (family-wise), z = %.1f; CV MSE now %.5f, by form: %s", step + 1,
                          in_.covariates.columns[c].name.c_str(), adjusted[k], t.z[k], cv_now, forms_text.c_str());
            report(line);
            if (best_cv < cv_now) {
                Term term;
                term.candidate = c;
                term.shape = best_shape_on_all(terms, cand, best_form);
                term.block = cand.block;
                term.factor = cand.factor;
                if (!term.block) term.basis = basis_of(in_.covariates.columns[c], term.shape);
                report("  accepted as " + best_form + ": " + describe_shape(term.shape));
                terms.push_back(std::move(term));
                refit_shapes(terms);
                remaining.erase(remaining.begin() + static_cast<std::ptrdiff_t>(k));
                accepted = true;
                tested_final_model = false;
                break;
            }
            report("  not accepted: no form lowers the cross-validated error");
        }
        if (!accepted) break;
    }

    // Backward: every kept term given all the others; drop the weakest until all hold.
    std::vector<double> kept_p(terms.size(), 0.0);
    for (std::uint64_t round = 0; !terms.empty(); ++round) {
        std::vector<double> p;
        for (std::size_t k = 0; k < terms.size(); ++k) {
            std::vector<Term> others = terms;
            others.erase(others.begin() + static_cast<std::ptrdiff_t>(k));
            const TestOutcome t = test(residual_after(others), design_of(others, true), std::vector<std::size_t>{terms[k].candidate}, 100 + round * 16 + k,
                                       "re-testing '" + in_.covariates.columns[terms[k].candidate].name + "' given the others");
            p.push_back(t.p[0]);
        }
        const auto adjusted = holm(p);
        const auto worst = static_cast<std::size_t>(std::max_element(adjusted.begin(), adjusted.end()) - adjusted.begin());
        if (adjusted[worst] <= opt_.alpha) {
            kept_p = adjusted;
            break;
        }
        report("backward: '" + in_.covariates.columns[terms[worst].candidate].name + "' no longer significant given the others (p = " +
               std::to_string(adjusted[worst]) + "): dropped");
        remaining.push_back(terms[worst].candidate);
        terms.erase(terms.begin() + static_cast<std::ptrdiff_t>(worst));
        tested_final_model = false;
    }
    if (!tested_final_model && !remaining.empty()) {
        const TestOutcome t = test(residual_after(terms), design_of(terms, true), remaining, 99, "final model: testing the rest");
        const auto& adjusted = t.adjusted;
        for (std::size_t k = 0; k < remaining.size(); ++k) given_model_p[remaining[k]] = adjusted[k];
    }

    // Interactions: does a kept cause's effect change with another column? For each kept numeric cause
    // a and every other numeric column b, the product (a's basis - its mean)(b - its mean), taken off b
    // itself so that a main effect of b cannot pass for one, is tested as a family given the model. A
    // significant one that lowers the cross-validated error is kept as two terms, a's basis times
    // (b - mean) and b's own linear term (the same span as the centred product with b), at most two
    // such pairs.
    std::vector<Term> interactions;
    for (int round = 0; round < 2; ++round) {
        std::vector<Term> model = terms;
        model.insert(model.end(), interactions.begin(), interactions.end());
        std::vector<Candidate> pairs;            // the test's column per pair
        std::vector<Candidate> products;         // the product a's basis x (b - mean), for the fit
        std::vector<Term> as_terms, companions;  // the terms a kept pair adds
        std::vector<VectorXd> linears;           // b - its mean, per pair
        for (const Term& a : terms) {
            if (a.block) continue;
            const double a_mean = a.basis.col(0).mean();
            for (std::size_t b = 0; b < candidates_.size(); ++b) {
                const CovariateColumn& column = in_.covariates.columns[candidates_[b].column];
                if (!column.numeric || b == a.candidate) continue;
                if (std::any_of(interactions.begin(), interactions.end(), [&](const Term& i) { return i.candidate == a.candidate && i.times == b; })) continue;
                const double mean = std::accumulate(column.values.begin(), column.values.end(), 0.0) / static_cast<double>(n);
                Term t = a;
                t.times = b;
                t.times_origin = mean;
                VectorXd centred(n_), linear(n_);
                for (Index i = 0; i < n_; ++i) {
                    linear(i) = column.values[static_cast<std::size_t>(i)] - mean;
                    t.basis(i, 0) = a.basis(i, 0) * linear(i);
                    centred(i) = (a.basis(i, 0) - a_mean) * linear(i);
                }
                const double ll = linear.squaredNorm();
                if (ll > 0.0) centred -= linear * (linear.dot(centred) / ll);
                Candidate c;
                c.column = a.candidate;
                c.shapes.push_back({"interaction", 0.0, mean});
                c.bases.push_back(centred);
                pairs.push_back(std::move(c));
                Candidate product;
                product.column = a.candidate;
                product.shapes.push_back({"interaction", 0.0, mean});
                product.bases.push_back(t.basis);
                products.push_back(std::move(product));
                Term main;
                main.candidate = b;
                main.shape = {"linear", 0.0, 0.0};
                main.basis = basis_of(column, main.shape);
                companions.push_back(std::move(main));
                as_terms.push_back(std::move(t));
                linears.push_back(linear);
            }
        }
        if (pairs.empty()) break;
        std::vector<const Candidate*> which;
        for (const auto& c : pairs) which.push_back(&c);
        const TestOutcome t = test(residual_after(model), design_of(model, true), which, 800 + static_cast<std::uint64_t>(round), "interactions between the causes");
        std::vector<std::size_t> order(pairs.size());
        std::iota(order.begin(), order.end(), std::size_t{0});
        std::sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) { return t.z[x] > t.z[y]; });
        const double cv_now = cv_mse(model, true, nullptr, "");
        bool added = false;
        for (std::size_t k : order) {
            const std::string a = in_.covariates.columns[as_terms[k].candidate].name;
            const std::string b = in_.covariates.columns[*as_terms[k].times].name;
            // Each pair once: a later round (given a kept interaction) updates its p.
            auto record = std::find_if(result_.interactions.begin(), result_.interactions.end(),
                                       [&](const InteractionCheck& i) { return i.covariate == a && i.times == b; });
            if (record == result_.interactions.end()) record = result_.interactions.insert(result_.interactions.end(), {a, b, t.adjusted[k], false, 0.0});
            else record->p_value = t.adjusted[k];
            if (added || t.adjusted[k] > opt_.alpha) continue;
            std::vector<Term> with_main = model;
            with_main.push_back(companions[k]);
            const double cv = cv_mse(with_main, true, &products[k], "interaction");
            char line[256];
            std::snprintf(line, sizeof line, "interaction '%s' x '%s': p = %.4g (family-wise over %zu pairs); CV MSE %.5f -> %.5f: %s", a.c_str(), b.c_str(),
                          t.adjusted[k], pairs.size(), cv_now, cv, cv < cv_now ? "kept" : "not worth a term");
            report(line);
            if (cv < cv_now) {
                // The cause's own shape again, now beside its interaction: chosen without it, a curve
                // (saturating, a power) bent to carry part of the interaction. Form by cross-validation,
                // parameter by least squares, the cause and its product together.
                const auto ia = static_cast<std::size_t>(std::find_if(terms.begin(), terms.end(), [&](const Term& x) { return x.candidate == as_terms[k].candidate; }) -
                                                         terms.begin());
                const Candidate& ca = candidates_[terms[ia].candidate];
                std::vector<Term> rest;
                for (std::size_t j = 0; j < model.size(); ++j) {
                    if (j != ia) rest.push_back(model[j]);
                }
                rest.push_back(companions[k]);
                Candidate joint;
                joint.column = ca.column;
                for (std::size_t sh = 0; sh < ca.shapes.size(); ++sh) {
                    if (ca.shapes[sh].form == "peaked" && terms[ia].shape.form != "peaked") continue;
                    MatrixXd both(n_, 2);
                    both.col(0) = ca.bases[sh].col(0);
                    both.col(1) = ca.bases[sh].col(0).cwiseProduct(linears[k]);
                    joint.shapes.push_back(ca.shapes[sh]);
                    joint.bases.push_back(std::move(both));
                }
                std::string form = terms[ia].shape.form;
                double best_form_cv = INFINITY;
                for (const auto& f : forms_for(in_.covariates.columns[ca.column])) {
                    if (f == "peaked" && terms[ia].shape.form != "peaked") continue;
                    const double fcv = cv_mse(rest, true, &joint, f);
                    if (fcv < best_form_cv) {
                        best_form_cv = fcv;
                        form = f;
                    }
                }
                const GroupedDesign base = design_of(rest, true);
                const RowList every = all_rows(n_);
                double best_sse = INFINITY;
                for (std::size_t sh = 0; sh < joint.shapes.size(); ++sh) {
                    if (joint.shapes[sh].form != form) continue;
                    GroupedDesign d;
                    d.dense.resize(n_, base.dense.cols() + 2);
                    d.dense << base.dense, joint.bases[sh];
                    d.factors = base.factors;
                    const double sse = (r_ - predict_grouped(d, fit_grouped(d, r_, every), every)).squaredNorm();
                    if (sse < best_sse) {
                        best_sse = sse;
                        terms[ia].shape = joint.shapes[sh];
                        terms[ia].basis = joint.bases[sh].col(0);
                        as_terms[k].shape = joint.shapes[sh];
                        as_terms[k].basis = joint.bases[sh].col(1);
                    }
                }
                report("  with it '" + a + "' is " + describe_shape(terms[ia].shape));
                interactions.push_back(companions[k]);
                interactions.push_back(as_terms[k]);
                record->kept = true;
                added = true;
            }
        }
        if (!added) break;
    }
    // Significant first, then by p.
    std::stable_sort(result_.interactions.begin(), result_.interactions.end(),
                     [](const InteractionCheck& x, const InteractionCheck& y) { return x.kept != y.kept ? x.kept : x.p_value < y.p_value; });
    // The causes, then the interactions: the causes' coefficients come first in every fit below.
    const std::size_t causes_count = terms.size();
    terms.insert(terms.end(), interactions.begin(), interactions.end());

    // The extended model: a level whenever anything is kept, and the terms.
    const bool extended = !terms.empty() || result_.calibration.significant;
    result_.discrepancy_found = extended;
    // The width of the causes' coefficients (after the intercept).
    auto causes_width = [](const std::vector<Term>& list, std::size_t count) {
        std::size_t w = 0;
        for (std::size_t k = 0; k < count; ++k) w += static_cast<std::size_t>(list[k].width());
        return w;
    };
    VectorXd fitted = VectorXd::Zero(n_);
    VectorXd oof = VectorXd::Zero(n_);
    if (extended) {
        const GroupedDesign design = design_of(terms, true);
        const RowList every_row = all_rows(n_);
        const VectorXd beta = coefficients_of(terms, fit_grouped(design, r_, every_row));
        fitted = r_ - residual_after(terms);
        cv_mse(terms, true, nullptr, "", &oof);
        result_.extension.push_back({.covariate = "level", .form = "constant", .coefficient = beta(0), .scale = 0.0, .category = {}, .origin = 0.0,
                                     .range_low = 0.0, .range_high = 0.0, .times_covariate = {}, .times_origin = 0.0, .times_low = 0.0, .times_high = 0.0});
        Index at = 1;
        const double total = std::max((r_.array() - r_.mean()).matrix().squaredNorm(), 1e-300);
        const double sse_full = (r_ - fitted).squaredNorm();
        for (std::size_t k = causes_count; k < terms.size(); ++k) {
            // An interaction: the cause's term times (the other column - its mean), held within the
            // other column's range and a tenth beyond; and that column's own linear term.
            const Term& t = terms[k];
            const CovariateColumn& column = in_.covariates.columns[t.candidate];
            auto term = terms_of(column, t.shape, beta.segment(1 + static_cast<Index>(causes_width(terms, causes_count)) + static_cast<Index>(k - causes_count), 1)).front();
            if (!t.times) {
                result_.extension.push_back(term);
                continue;
            }
            const CovariateColumn& other = in_.covariates.columns[*t.times];
            const auto [lo, hi] = std::minmax_element(other.values.begin(), other.values.end());
            term.times_covariate = other.name;
            term.times_origin = t.times_origin;
            term.times_low = *lo - 0.1 * (*hi - *lo);
            term.times_high = *hi + 0.1 * (*hi - *lo);
            for (auto& i : result_.interactions) {
                if (i.kept && i.covariate == column.name && i.times == other.name) i.coefficient = term.coefficient;
            }
            result_.extension.push_back(term);
        }
        for (std::size_t k = 0; k < causes_count; ++k) {
            const Term& t = terms[k];
            const CovariateColumn& column = in_.covariates.columns[t.candidate];
            Cause cause;
            cause.covariate = column.name;
            cause.shape = t.shape;
            cause.coefficients = beta.segment(at, t.width());
            at += t.width();
            const auto terms_here = terms_of(column, t.shape, cause.coefficients);
            result_.extension.insert(result_.extension.end(), terms_here.begin(), terms_here.end());
            if (column.numeric) {
                const bool step = t.shape.form == "step";
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
                    cause.curve_factor.push_back(std::exp(cause.coefficients(0) * basis_value(t.shape, x)));
                }
            } else {
                cause.reference = column.levels[0];
                cause.level_share.assign(column.levels.size(), 0.0);
                for (auto l : column.level) cause.level_share[l] += 1.0 / static_cast<double>(n);
                cause.curve_x.push_back(0.0);
                cause.curve_factor.push_back(1.0);
                for (Index l = 0; l < cause.coefficients.size(); ++l) {
                    cause.curve_x.push_back(static_cast<double>(l + 1));
                    cause.curve_factor.push_back(std::exp(cause.coefficients(l)));
                }
            }
            std::size_t level = 0;
            cause.effect_size = effect_of(cause, cause.coefficients, &level);
            if (!column.numeric) cause.category = column.levels[level];
            cause.direction = t.shape.form == "peaked" ? "nonmonotone" : cause.effect_size >= 0.0 ? "increases" : "decreases";
            cause.p_value = kept_p[k];
            std::vector<Term> others = terms;
            others.erase(others.begin() + static_cast<std::ptrdiff_t>(k));
            cause.importance = (residual_after(others).squaredNorm() - sse_full) / total;
            result_.causes.push_back(std::move(cause));
            result_.diagnostics[t.candidate].cause = true;
            // The screening's strongest single shape can differ from the one the cause was fitted with
            // (chosen by cross-validation, a peak only when it turns): the table says the cause's.
            result_.diagnostics[t.candidate].best_shape = describe_shape(t.shape);
            given_model_p[t.candidate] = kept_p[k];
        }
        // Intervals: resample whole flowers, refit the same terms at the same shapes.
        std::vector<std::vector<double>> effects(causes_count);
        std::vector<double> levels;
        std::mt19937_64 rng(opt_.seed ^ 0xB007B007ULL);
        std::uniform_int_distribution<std::size_t> pick(0, groups_.rows.size() - 1);
        for (std::uint32_t b = 0; b < opt_.bootstrap; ++b) {
            RowList rows;
            for (std::size_t g = 0; g < groups_.rows.size(); ++g) {
                const Rows& gr = groups_.rows[pick(rng)];
                rows.insert(rows.end(), gr.begin(), gr.end());
            }
            const GroupedFit fit = fit_grouped(design, r_, rows);
            const VectorXd bb = coefficients_of(terms, fit);
            levels.push_back(std::exp(predict_grouped(design, fit, every_row).mean()));
            Index a = 1;
            for (std::size_t k = 0; k < causes_count; ++k) {
                const VectorXd coefficients = bb.segment(a, terms[k].width());
                a += terms[k].width();
                // A category: the same level as the point estimate, not whichever differs most here.
                std::size_t level = 0;
                effect_of(result_.causes[k], result_.causes[k].coefficients, &level);
                if (terms[k].block) {
                    // A resample without one of its levels knows nothing of that level's effect (it enters
                    // as the mean) and pulls the interval toward 0: such a resample says nothing here.
                    const auto& of_row = *terms[k].factor.level;
                    std::vector<bool> present(terms[k].factor.levels, false);
                    for (Index i : rows) present[of_row[static_cast<std::size_t>(i)]] = true;
                    if (std::find(present.begin(), present.end(), false) != present.end()) continue;
                }
                effects[k].push_back(effect_of(result_.causes[k], coefficients, nullptr, level));
            }
        }
        for (std::size_t k = 0; k < causes_count; ++k) {
            if (effects[k].empty()) effects[k].push_back(result_.causes[k].effect_size); // no resample had the level
            result_.causes[k].effect_low = quantile(effects[k], 0.025);
            result_.causes[k].effect_high = quantile(effects[k], 0.975);
        }
        result_.calibration.factor = std::exp(fitted.mean());
        result_.calibration.low = quantile(levels, 0.025);
        result_.calibration.high = quantile(levels, 0.975);
        std::stable_sort(result_.causes.begin(), result_.causes.end(), [](const Cause& a, const Cause& b) { return a.importance > b.importance; });
    }
    for (std::size_t c = 0; c < candidates_.size(); ++c) result_.diagnostics[c].p_given_model = given_model_p[c];
    result_.fitted_log_factor.assign(fitted.data(), fitted.data() + n_);
    result_.cv_log_factor.assign(oof.data(), oof.data() + n_);
    result_.extended_rmse_gf = extended ? rmse_gf(in_, &fitted) : result_.baseline_rmse_gf;
    result_.extended_cv_rmse_gf = extended ? rmse_gf(in_, &oof) : result_.baseline_cv_rmse_gf;
    result_.extended_log_rmse = std::sqrt((r_ - fitted).squaredNorm() / static_cast<double>(n));
    result_.gain = extended && result_.baseline_cv_rmse_gf > 0.0 ? 1.0 - result_.extended_cv_rmse_gf / result_.baseline_cv_rmse_gf : 0.0;
    return std::move(result_);
}

} // namespace

namespace {

// Screens the categorical columns too wide for a per-level factor (AnalysisOptions says when) and
// returns the input without them. A per-level factor would be a dense design column per level: 60,000
// rows of a 10,000-level lot number are 4.8 GB before a single permutation.
AnalysisInput screened_input(const AnalysisInput& input, const AnalysisOptions& options, std::vector<ScreenedColumn>& screened) {
    AnalysisInput kept;
    kept.flower = input.flower;
    kept.measured_gf = input.measured_gf;
    kept.predicted_gf = input.predicted_gf;
    kept.covariates.constant = input.covariates.constant;
    const std::size_t n = input.measured_gf.size();
    std::vector<double> r(n);
    double mean = 0.0;
    for (std::size_t i = 0; i < n; ++i) mean += (r[i] = std::log(input.measured_gf[i] / input.predicted_gf[i])) / static_cast<double>(n);
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

namespace {

// The input without the rows in `out` (sorted).
AnalysisInput without_rows(const AnalysisInput& in, const std::vector<std::size_t>& out) {
    std::vector<bool> drop(in.measured_gf.size(), false);
    for (std::size_t i : out) drop[i] = true;
    AnalysisInput kept;
    kept.covariates.constant = in.covariates.constant;
    for (const auto& c : in.covariates.columns) {
        CovariateColumn k = c;
        k.values.clear();
        k.level.clear();
        kept.covariates.columns.push_back(std::move(k));
    }
    for (std::size_t i = 0; i < drop.size(); ++i) {
        if (drop[i]) continue;
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

Result<AnalysisResult> analyse_rows(const AnalysisInput& input, const AnalysisOptions& options) {
    std::vector<ScreenedColumn> screened;
    AnalysisInput kept = screened_input(input, options, screened);
    drop_untestable(kept);
    if (const auto [bytes, widest] = working_memory(kept); bytes > options.memory_budget_bytes) {
        return make_error(ErrorCode::invalid_argument,
                          "the covariates would need " + std::to_string(bytes >> 10) + " KiB of working memory, more than the " +
                              std::to_string(options.memory_budget_bytes >> 10) + " KiB budget; the widest is the column '" + widest +
                              "': leave it out (--ignore " + widest + ") or split the file");
    }
    Analysis analysis(kept, options);
    auto result = analysis.run();
    if (result) result->screened = std::move(screened);
    return result;
}

} // namespace

Result<AnalysisResult> analyse_discrepancy(const AnalysisInput& input, const AnalysisOptions& options) {
    if (options.permutations < 19) return make_error(ErrorCode::invalid_argument, "at least 19 permutations are needed for p < 0.05");
    const std::size_t n = input.measured_gf.size();
    if (options.outlier_z <= 0.0 || n < 20 || input.predicted_gf.size() != n || input.flower.size() != n) return analyse_rows(input, options);
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
