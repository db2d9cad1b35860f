// The analysis' permutation tests (discrepancy_analysis.hpp, "Tests"): each candidate's share of a
// residual against the residual permuted with each flower's rows kept together, corrected for the
// family by Westfall-Young step-down maxT; and the overall level against sign flips of whole flowers.
#include "game/analysis/discrepancy_tools.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>

namespace ikebana::game::discrepancy {

using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;

namespace {

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

// One candidate among the tested columns.
struct Span {
    Index begin, end;
    bool block;
    std::vector<std::size_t> shape_of_column;
    Index line = -1;    // the straight line's column among begin..end, when the column has one
    MatrixXd whitening; // block
    const Factor* factor = nullptr;
};

// Every numeric candidate's shapes side by side, orthonormal to the model: a statistic is then a
// dot product. A categorical candidate's is its whitened level sums (factor_whitening).
struct Columns {
    Eigen::MatrixXf w;
    std::vector<Span> spans;
    bool any_block = false;
};

Columns columns_of(const std::vector<const Candidate*>& which, const DesignComplement& model, Index n) {
    Columns out;
    std::vector<MatrixXd> parts;
    Index cols = 0;
    for (const Candidate* candidate : which) {
        const Candidate& cand = *candidate;
        Span s{cols, cols, cand.block, {}, -1, {}, nullptr};
        if (cand.block) {
            s.whitening = level_whitening(cand.factor, model, n);
            s.factor = &cand.factor;
            out.any_block = true;
        } else {
            for (std::size_t k = 0; k < cand.bases.size(); ++k) {
                MatrixXd w = orthonormal_rest(cand.bases[k], model);
                if (cand.shapes[k].form == "linear" && w.cols() == 1 && w.col(0).squaredNorm() > 0.0) s.line = cols;
                for (Index j = 0; j < w.cols(); ++j) s.shape_of_column.push_back(k);
                cols += w.cols();
                parts.push_back(std::move(w));
            }
        }
        s.end = cols;
        out.spans.push_back(std::move(s));
    }
    out.w.resize(n, cols);
    Index at = 0;
    for (const auto& p : parts) {
        out.w.middleCols(at, p.cols()) = p.cast<float>();
        at += p.cols();
    }
    return out;
}

// g: the numeric columns' dot products; off: the vectors themselves off the model (for factors).
double statistic(const Span& s, const Eigen::MatrixXf& g, const MatrixXd& off, Index column_of_perm, std::size_t* best) {
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
}

// The straight line's share alone; -1 when the column has none.
double line_statistic(const Span& s, const Eigen::MatrixXf& g, Index column_of_perm) {
    if (s.line < 0) return -1.0;
    const double v = static_cast<double>(g(s.line, column_of_perm));
    return v * v;
}

// A statistic's surprise: -ln of its upper tail under a gamma matched to its permutation mean and
// variance, in nats (about Exp(1) under the null, whatever the statistic's own scale). One whose
// permuted values hardly vary (or whose match is not finite) is scored by its rank among them.
class TailScore {
public:
    TailScore(const std::vector<double>& values, std::size_t stride, std::size_t at, std::uint32_t count) : count_(count) {
        double mean = 0.0;
        for (std::uint32_t b = 0; b < count; ++b) mean += values[b * stride + at];
        mean /= std::max(1u, count);
        double var = 0.0; // two passes: E[s^2] - mean^2 cancels when they are nearly equal
        for (std::uint32_t b = 0; b < count; ++b) var += (values[b * stride + at] - mean) * (values[b * stride + at] - mean);
        var /= std::max(1u, count);
        k_ = mean > 0.0 && var > 0.0 ? mean * mean / var : 0.0;
        theta_ = mean > 0.0 && var > 0.0 ? var / mean : 0.0;
        if (!(var > 1e-12 * mean * mean) || !std::isfinite(k_) || k_ > 1e6) {
            for (std::uint32_t b = 0; b < count; ++b) by_rank_.push_back(values[b * stride + at]);
            std::sort(by_rank_.begin(), by_rank_.end());
        }
    }
    double operator()(double x) const {
        if (!by_rank_.empty()) {
            const auto above = static_cast<double>(by_rank_.end() - std::lower_bound(by_rank_.begin(), by_rank_.end(), x * (1.0 - 1e-9)));
            return -std::log((1.0 + above) / (1.0 + static_cast<double>(count_)));
        }
        const double t = gamma_tail_score(x / theta_, k_);
        return std::isfinite(t) ? t : 0.0;
    }

private:
    std::uint32_t count_;
    double k_ = 0.0, theta_ = 0.0;
    std::vector<double> by_rank_;
};

// Every candidate's test statistic on each permutation of e, and how they compare with the observed
// ones. A column with a straight line is tested by two statistics, its line alone and its best shape
// of all, and scored by the larger surprise after weighing them as Bonferroni would split alpha:
// line_share to the line, the rest to the search. The best of ~40 shapes alone pays for the whole
// search even when a line is all there is: on 72 flowers differing by 12 % a trend was named in 71
// of 160 seeds where a flower-level regression found 93; weighed, 86 (flower_variation_test.cpp,
// docs/measured-data.md). A step or a peak still has the whole family, at a fifth of alpha.
constexpr double line_share = 0.8;

struct Permuted {
    std::vector<double> values; // [b * C + c], the combined surprise
    std::vector<std::size_t> exceed;
    std::vector<double> sum, sum_sq;
    std::vector<double> observed; // per candidate, the combined surprise of the observed residual
};

Permuted permuted_statistics(const Analysis& a, const Columns& columns, const VectorXd& e, const DesignComplement& model,
                             const std::vector<double>& observed_all, const std::vector<double>& observed_line, double total, std::uint64_t stream,
                             const std::string& stage) {
    const std::size_t m = columns.spans.size();
    const std::uint32_t b_total = a.opt.permutations;
    const std::size_t cells = static_cast<std::size_t>(b_total) * m;
    std::vector<double> all(cells), line(cells, -1.0);
    std::mt19937_64 rng(a.opt.seed * 0x9E3779B97F4A7C15ULL + stream);
    ResidualPermuter permuter(a.groups);
    constexpr std::uint32_t batch = 64;
    Eigen::MatrixXf perm(a.n, batch);
    MatrixXd perm_off; // the batch off the model, when a factor is tested
    for (std::uint32_t done = 0; done < b_total;) {
        const std::uint32_t now = std::min(batch, b_total - done);
        for (std::uint32_t k = 0; k < now; ++k) permuter.permute(e, rng, perm.col(k).data());
        const Eigen::MatrixXf g = columns.w.transpose() * perm.leftCols(now);
        if (columns.any_block) {
            perm_off = perm.leftCols(now).cast<double>();
            model.apply(perm_off);
        }
        for (std::uint32_t k = 0; k < now; ++k) {
            for (std::size_t c = 0; c < m; ++c) {
                all[(done + k) * m + c] = statistic(columns.spans[c], g, perm_off, static_cast<Index>(k), nullptr) / total;
                line[(done + k) * m + c] = line_statistic(columns.spans[c], g, static_cast<Index>(k)) / total;
            }
        }
        done += now;
        if (a.opt.progress) a.opt.progress(stage, done, b_total);
    }
    Permuted out{std::vector<double>(cells), std::vector<std::size_t>(m, 0), std::vector<double>(m, 0.0), std::vector<double>(m, 0.0), std::vector<double>(m, 0.0)};
    for (std::size_t c = 0; c < m; ++c) {
        const bool has_line = columns.spans[c].line >= 0;
        const TailScore score_all(all, m, c, b_total);
        if (!has_line) {
            out.observed[c] = observed_all[c];
            for (std::uint32_t b = 0; b < b_total; ++b) out.values[b * m + c] = all[b * m + c];
        }
        const TailScore score_line(line, m, c, has_line ? b_total : 0u);
        const auto combined = [&](double v_all, double v_line) { return has_line ? std::max(score_all(v_all) + std::log(1.0 - line_share), score_line(v_line) + std::log(line_share)) : v_all; };
        out.observed[c] = combined(observed_all[c], observed_line[c]);
        for (std::uint32_t b = 0; b < b_total; ++b) {
            const double v = combined(all[b * m + c], line[b * m + c]);
            out.values[b * m + c] = v;
            out.sum[c] += v;
            out.sum_sq[c] += v * v;
            if (v >= out.observed[c] * (1.0 - 1e-6)) ++out.exceed[c];
        }
    }
    return out;
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
std::vector<double> step_down_max_t(const std::vector<double>& observed, const std::vector<double>& p, const Permuted& permuted, std::uint32_t b_total) {
    const std::size_t m = observed.size();
    std::vector<TailScore> scores;
    for (std::size_t c = 0; c < m; ++c) scores.emplace_back(permuted.values, m, c, b_total);
    auto score = [&](std::size_t c, double x) { return scores[c](x); };
    std::vector<double> observed_score(m);
    for (std::size_t c = 0; c < m; ++c) observed_score[c] = score(c, observed[c]);
    std::vector<std::size_t> order(m);
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return observed_score[a] > observed_score[b]; });
    std::vector<std::size_t> count(m, 0);
    for (std::uint32_t b = 0; b < b_total; ++b) {
        // Successive maxima from the least significant up.
        double running = -INFINITY;
        for (std::size_t j = m; j-- > 0;) {
            const std::size_t c = order[j];
            running = std::max(running, score(c, permuted.values[b * m + c]));
            if (running >= observed_score[c] * (1.0 - 1e-9)) ++count[j];
        }
    }
    std::vector<double> adjusted(m, 1.0);
    double previous = 0.0;
    for (std::size_t j = 0; j < m; ++j) {
        const double pj = std::max(previous, (1.0 + static_cast<double>(count[j])) / (1.0 + b_total));
        adjusted[order[j]] = std::max(pj, p[order[j]]);
        previous = adjusted[order[j]];
    }
    return adjusted;
}

} // namespace

TestOutcome Analysis::test(const VectorXd& residual, const GroupedDesign& design, const std::vector<std::size_t>& which, std::uint64_t stream,
                           const std::string& stage) const {
    std::vector<const Candidate*> tested;
    for (std::size_t c : which) tested.push_back(&candidates[c]);
    return test(residual, design, tested, stream, stage);
}

TestOutcome Analysis::test(const VectorXd& residual, const GroupedDesign& design, const std::vector<const Candidate*>& which, std::uint64_t stream,
                           const std::string& stage) const {
    const DesignComplement model(design);
    VectorXd e = residual;
    model.apply(e);
    const double total = std::max(e.squaredNorm(), 1e-300);
    const Columns columns = columns_of(which, model, n);
    TestOutcome out;
    const Eigen::VectorXf ef = e.cast<float>();
    const Eigen::MatrixXf g0 = columns.w.transpose() * ef;
    const MatrixXd e_off = e; // already off the model
    std::vector<double> line;
    for (std::size_t c = 0; c < which.size(); ++c) {
        std::size_t best = 0;
        out.observed.push_back(statistic(columns.spans[c], g0, e_off, 0, &best) / total);
        out.best_shape.push_back(best);
        line.push_back(line_statistic(columns.spans[c], g0, 0) / total);
    }
    const Permuted permuted = permuted_statistics(*this, columns, e, model, out.observed, line, total, stream, stage);
    const std::uint32_t b_total = opt.permutations;
    for (std::size_t c = 0; c < which.size(); ++c) {
        out.p.push_back((1.0 + static_cast<double>(permuted.exceed[c])) / (1.0 + b_total));
        const double mean = permuted.sum[c] / std::max(1u, b_total);
        const double sd = std::sqrt(std::max(permuted.sum_sq[c] / std::max(1u, b_total) - mean * mean, 1e-300));
        out.z.push_back((permuted.observed[c] - mean) / sd);
    }
    out.adjusted = step_down_max_t(permuted.observed, out.p, permuted, b_total);
    return out;
}

// The overall level: |mean residual| against sign flips of whole flowers.
double Analysis::level_p_value(const VectorXd& residual, std::uint64_t stream) const {
    std::vector<double> sums;
    for (const auto& rows : groups.rows) {
        double s = 0.0;
        for (Index i : rows) s += residual(i);
        sums.push_back(s);
    }
    const double observed = std::abs(std::accumulate(sums.begin(), sums.end(), 0.0));
    std::mt19937_64 rng(opt.seed * 0x9E3779B97F4A7C15ULL + stream);
    std::size_t exceed = 0;
    for (std::uint32_t b = 0; b < opt.permutations; ++b) {
        double s = 0.0;
        for (double v : sums) s += (rng() & 1U) ? v : -v;
        if (std::abs(s) >= observed * (1.0 - 1e-9)) ++exceed;
    }
    return (1.0 + static_cast<double>(exceed)) / (1.0 + opt.permutations);
}

} // namespace ikebana::game::discrepancy
