// The analysis' first three stages: screening, forward selection and backward elimination.
#include "game/analysis/discrepancy_stages.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>

namespace ikebana::game::discrepancy {

using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;

namespace {

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

std::vector<std::size_t> every_candidate(const Analysis& a) {
    std::vector<std::size_t> all(a.candidates.size());
    std::iota(all.begin(), all.end(), std::size_t{0});
    return all;
}

} // namespace

Screening screen(const Analysis& a) {
    Screening out;
    const double level_p = a.level_p_value(a.r, 0);
    GroupedDesign intercept_only;
    intercept_only.dense = MatrixXd::Ones(a.n, 1);
    out.first = a.test(a.r, intercept_only, every_candidate(a), 1, "testing every covariate");
    for (std::size_t c = 0; c < a.candidates.size(); ++c) {
        const auto& column = a.column_of(c);
        CovariateDiagnostic d;
        d.covariate = column.name;
        d.numeric = column.numeric;
        d.bins = bins_of(column, a.r);
        d.strength = out.first.observed[c];
        d.best_shape = describe_shape(a.candidates[c].shapes[out.first.best_shape[c]]);
        d.p_value = out.first.p[c];
        d.p_adjusted = out.first.adjusted[c];
        d.blank = column.missing;
        d.blank_value = column.fill_value;
        out.diagnostics.push_back(std::move(d));
    }
    // The level is a family of its own: is the simulation's scale off at all?
    out.calibration.p_value = level_p;
    const double cv_none = a.cv_mse({}, false, nullptr, "");
    const double cv_level = a.cv_mse({}, true, nullptr, "");
    out.calibration.significant = level_p <= a.opt.alpha && cv_level < cv_none;
    char line[200];
    std::snprintf(line, sizeof line, "overall level: %s = %.3f, p = %.4g, CV %s %.5f -> %.5f with a level: %s",
                  a.in.observed == Observed::outcome ? "fell - chance" : "measured/predicted", a.in.observed == Observed::outcome ? a.r.mean() : std::exp(a.r.mean()),
                  level_p, a.loss_name(), cv_none, cv_level, out.calibration.significant ? "kept" : "not kept");
    out.log.push_back(line);
    return out;
}

namespace {

// A form for a candidate given the terms, with every form's cross-validated error in words.
struct FormChoice {
    std::string form;
    double cv = INFINITY;
    std::string text;
};

// The turn in candidate c beyond its monotone form: its peaked shapes, tested on what that form leaves.
double turn_p_value(const Analysis& a, const std::vector<Term>& terms, std::size_t c, const std::string& monotone, std::uint32_t step) {
    const Candidate& cand = a.candidates[c];
    std::vector<Term> with_monotone = terms;
    with_monotone.push_back(a.make_term(c, a.best_shape_on_all(terms, cand, monotone)));
    Candidate peaks;
    peaks.column = c;
    for (std::size_t s = 0; s < cand.shapes.size(); ++s) {
        if (cand.shapes[s].form != "peaked") continue;
        peaks.shapes.push_back(cand.shapes[s]);
        peaks.bases.push_back(cand.bases[s]);
    }
    const TestOutcome turn = a.test(a.residual_after(with_monotone), a.design_of(with_monotone, true), std::vector<const Candidate*>{&peaks}, 500 + step,
                                    "does '" + a.column_of(c).name + "' turn?");
    return turn.p[0];
}

FormChoice choose_form(const Analysis& a, const std::vector<Term>& terms, std::size_t c, std::uint32_t step) {
    FormChoice best, monotone;
    for (const auto& form : forms_for(a.column_of(c))) {
        const double cv = a.cv_mse(terms, true, &a.candidates[c], form);
        char part[64];
        std::snprintf(part, sizeof part, "%s%s %.5f", best.text.empty() ? "" : ", ", form.c_str(), cv);
        best.text += part;
        if (cv < best.cv) {
            best.cv = cv;
            best.form = form;
        }
        if (form != "peaked" && cv < monotone.cv) {
            monotone.cv = cv;
            monotone.form = form;
        }
    }
    // A peak or trough must be shown to turn, not just fit a little better: a fast saturating
    // decay is fitted about as well by a trough near its flat end, whose rise past the vertex no
    // data shows. So the peaked shapes are tested, with permutations as every candidate is, on
    // what the best monotone form leaves; without a significant turn the form stays monotone.
    if (best.form == "peaked" && !monotone.form.empty()) {
        const double p = turn_p_value(a, terms, c, monotone.form, step);
        char part[96];
        std::snprintf(part, sizeof part, "; a turn beyond %s: p = %.4g", monotone.form.c_str(), p);
        best.text += part;
        if (p > a.opt.alpha) {
            best.form = monotone.form;
            best.cv = monotone.cv;
        }
    }
    return best;
}

// One step of forward selection given the test of the remaining candidates: the most significant
// candidate whose best form lowers the cross-validated error joins the terms. False: none did.
bool accept_one(const Analysis& a, const TestOutcome& t, std::uint32_t step, Selection& s) {
    std::vector<std::size_t> significant;
    for (std::size_t k = 0; k < s.remaining.size(); ++k) {
        if (t.adjusted[k] <= a.opt.alpha) significant.push_back(k);
    }
    std::sort(significant.begin(), significant.end(), [&](std::size_t x, std::size_t y) { return t.z[x] > t.z[y]; });
    const double cv_now = a.cv_mse(s.terms, true, nullptr, "");
    for (std::size_t k : significant) {
        const std::size_t c = s.remaining[k];
        const FormChoice form = choose_form(a, s.terms, c, step);
        char line[512];
        std::snprintf(line, sizeof line, "step %u: '%s' p = %.4g (family-wise), z = %.1f; CV %s now %.5f, by form: %s", step + 1, a.column_of(c).name.c_str(),
                      t.adjusted[k], t.z[k], a.loss_name(), cv_now, form.text.c_str());
        s.log.push_back(line);
        if (form.cv < cv_now) {
            Term term = a.make_term(c, a.best_shape_on_all(s.terms, a.candidates[c], form.form));
            s.log.push_back("  accepted as " + form.form + ": " + describe_shape(term.shape));
            s.terms.push_back(std::move(term));
            a.refit_shapes(s.terms, s.log);
            s.remaining.erase(s.remaining.begin() + static_cast<std::ptrdiff_t>(k));
            s.tested_final_model = false;
            return true;
        }
        s.log.push_back("  not accepted: no form lowers the cross-validated error");
    }
    return false;
}

} // namespace

Selection select_forward(const Analysis& a, const TestOutcome& first) {
    Selection s;
    s.remaining = every_candidate(a);
    s.given_model_p.assign(a.candidates.size(), 1.0);
    for (std::uint32_t step = 0; step < a.opt.max_terms && !s.remaining.empty(); ++step) {
        const TestOutcome t = step == 0 ? first
                                        : a.test(a.residual_after(s.terms), a.design_of(s.terms, true), s.remaining, 2 + step,
                                                 "step " + std::to_string(step + 1) + ": given " + std::to_string(s.terms.size()) + " term(s)");
        for (std::size_t k = 0; k < s.remaining.size(); ++k) s.given_model_p[s.remaining[k]] = t.adjusted[k];
        s.tested_final_model = true;
        if (!accept_one(a, t, step, s)) break;
    }
    return s;
}

Elimination eliminate_backward(const Analysis& a, const Selection& forward) {
    Elimination out;
    out.terms = forward.terms;
    out.given_model_p = forward.given_model_p;
    std::vector<std::size_t> remaining = forward.remaining;
    bool tested_final_model = forward.tested_final_model;
    // Backward: every kept term given all the others; drop the weakest until all hold.
    out.kept_p.assign(out.terms.size(), 0.0);
    for (std::uint64_t round = 0; !out.terms.empty(); ++round) {
        std::vector<double> p;
        for (std::size_t k = 0; k < out.terms.size(); ++k) {
            std::vector<Term> others = out.terms;
            others.erase(others.begin() + static_cast<std::ptrdiff_t>(k));
            const TestOutcome t = a.test(a.residual_after(others), a.design_of(others, true), std::vector<std::size_t>{out.terms[k].candidate},
                                         100 + round * 16 + k, "re-testing '" + a.column_of(out.terms[k].candidate).name + "' given the others");
            p.push_back(t.p[0]);
        }
        const auto adjusted = holm(p);
        const auto worst = static_cast<std::size_t>(std::max_element(adjusted.begin(), adjusted.end()) - adjusted.begin());
        if (adjusted[worst] <= a.opt.alpha) {
            out.kept_p = adjusted;
            break;
        }
        out.log.push_back("backward: '" + a.column_of(out.terms[worst].candidate).name + "' no longer significant given the others (p = " +
                          std::to_string(adjusted[worst]) + "): dropped");
        remaining.push_back(out.terms[worst].candidate);
        out.terms.erase(out.terms.begin() + static_cast<std::ptrdiff_t>(worst));
        tested_final_model = false;
    }
    if (!tested_final_model && !remaining.empty()) {
        const TestOutcome t = a.test(a.residual_after(out.terms), a.design_of(out.terms, true), remaining, 99, "final model: testing the rest");
        for (std::size_t k = 0; k < remaining.size(); ++k) out.given_model_p[remaining[k]] = t.adjusted[k];
    }
    return out;
}

} // namespace ikebana::game::discrepancy
