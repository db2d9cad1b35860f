// Interactions: does a kept cause's effect change with another column? For each kept numeric cause
// a and every other numeric column b, the product (a's basis - its mean)(b - its mean), taken off b
// itself so that a main effect of b cannot pass for one, is tested as a family given the model. A
// significant one that lowers the cross-validated error is kept as two terms, a's basis times
// (b - mean) and b's own linear term (the same span as the centred product with b), at most two
// such pairs.
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

// A cause and a column its effect may change with.
struct Pair {
    Candidate tested;  // the test's column: the centred product, off the column itself
    Candidate product; // the product the cause's basis x (column - mean), for the fit
    Term term;         // that product as the term a kept pair adds
    Term companion;    // and the column's own linear term, which it adds too
    VectorXd linear;   // the column - its mean
};

// Every pair of a kept numeric cause and another numeric column, but those already kept.
std::vector<Pair> pairs_of(const Analysis& a, const std::vector<Term>& causes, const std::vector<Term>& kept) {
    std::vector<Pair> pairs;
    for (const Term& cause : causes) {
        if (cause.block) continue;
        const double cause_mean = cause.basis.col(0).mean();
        for (std::size_t b = 0; b < a.candidates.size(); ++b) {
            const CovariateColumn& column = a.column_of(a.candidates[b].column);
            if (!column.numeric || b == cause.candidate) continue;
            if (std::any_of(kept.begin(), kept.end(), [&](const Term& i) { return i.candidate == cause.candidate && i.times == b; })) continue;
            const double mean = std::accumulate(column.values.begin(), column.values.end(), 0.0) / static_cast<double>(a.in.measured_gf.size());
            Pair p;
            p.term = cause;
            p.term.times = b;
            p.term.times_origin = mean;
            VectorXd centred(a.n);
            p.linear.resize(a.n);
            for (Index i = 0; i < a.n; ++i) {
                p.linear(i) = column.values[static_cast<std::size_t>(i)] - mean;
                p.term.basis(i, 0) = cause.basis(i, 0) * p.linear(i);
                centred(i) = (cause.basis(i, 0) - cause_mean) * p.linear(i);
            }
            const double ll = p.linear.squaredNorm();
            if (ll > 0.0) centred -= p.linear * (p.linear.dot(centred) / ll);
            p.tested.column = cause.candidate;
            p.tested.shapes.push_back({"interaction", 0.0, mean});
            p.tested.bases.push_back(centred);
            p.product.column = cause.candidate;
            p.product.shapes.push_back({"interaction", 0.0, mean});
            p.product.bases.push_back(p.term.basis);
            p.companion.candidate = b;
            p.companion.shape = {"linear", 0.0, 0.0};
            p.companion.basis = basis_of(column, p.companion.shape);
            pairs.push_back(std::move(p));
        }
    }
    return pairs;
}

// Whether the model already has the column's own linear term (a cause of that form, or the companion of
// an earlier interaction with it): a second would be the same column twice, and the fit's two
// coefficients for it then grew without bound in opposite directions (an effect of +inf was reported).
bool has_linear_term(const std::vector<Term>& model, std::size_t candidate) {
    return std::any_of(model.begin(), model.end(), [&](const Term& t) { return t.candidate == candidate && !t.times && t.shape.form == "linear"; });
}

// The cause's every shape beside its product with the pair's column: two columns a shape.
Candidate joint_of(const Candidate& cause, const Term& term, const VectorXd& linear, Index n) {
    Candidate joint;
    joint.column = cause.column;
    for (std::size_t sh = 0; sh < cause.shapes.size(); ++sh) {
        if (cause.shapes[sh].form == "peaked" && term.shape.form != "peaked") continue;
        MatrixXd both(n, 2);
        both.col(0) = cause.bases[sh].col(0);
        both.col(1) = cause.bases[sh].col(0).cwiseProduct(linear);
        joint.shapes.push_back(cause.shapes[sh]);
        joint.bases.push_back(std::move(both));
    }
    return joint;
}

// The cause's own shape again, now beside its interaction: chosen without it, a curve
// (saturating, a power) bent to carry part of the interaction. Form by cross-validation,
// parameter by least squares, the cause and its product together.
void reshape_beside(const Analysis& a, const std::vector<Term>& model, Pair& pair, Interactions& out) {
    std::vector<Term>& terms = out.causes;
    const auto ia = static_cast<std::size_t>(std::find_if(terms.begin(), terms.end(), [&](const Term& x) { return x.candidate == pair.term.candidate; }) -
                                             terms.begin());
    const Candidate& ca = a.candidates[terms[ia].candidate];
    std::vector<Term> rest;
    for (std::size_t j = 0; j < model.size(); ++j) {
        if (j != ia) rest.push_back(model[j]);
    }
    if (!has_linear_term(rest, pair.companion.candidate)) rest.push_back(pair.companion);
    const Candidate joint = joint_of(ca, terms[ia], pair.linear, a.n);
    std::string form = terms[ia].shape.form;
    double best_form_cv = INFINITY;
    for (const auto& f : forms_for(a.column_of(ca.column))) {
        if (f == "peaked" && terms[ia].shape.form != "peaked") continue;
        const double fcv = a.cv_mse(rest, true, &joint, f);
        if (fcv < best_form_cv) {
            best_form_cv = fcv;
            form = f;
        }
    }
    const GroupedDesign base = a.design_of(rest, true);
    const RowList every = all_rows(a.n);
    double best_sse = INFINITY;
    for (std::size_t sh = 0; sh < joint.shapes.size(); ++sh) {
        if (joint.shapes[sh].form != form) continue;
        GroupedDesign d;
        d.dense.resize(a.n, base.dense.cols() + 2);
        d.dense << base.dense, joint.bases[sh];
        d.factors = base.factors;
        const double sse = (a.r - predict_grouped(d, fit_grouped(d, a.r, every), every)).squaredNorm();
        if (sse < best_sse) {
            best_sse = sse;
            terms[ia].shape = joint.shapes[sh];
            terms[ia].basis = joint.bases[sh].col(0);
            pair.term.shape = joint.shapes[sh];
            pair.term.basis = joint.bases[sh].col(1);
        }
    }
    out.log.push_back("  with it '" + a.column_of(pair.term.candidate).name + "' is " + describe_shape(terms[ia].shape));
}

// One round: the pairs tested as a family given the model, each recorded; the most significant that
// lowers the cross-validated error is kept. False: none was.
bool add_one(const Analysis& a, const std::vector<Term>& model, std::vector<Pair>& pairs, int round, Interactions& out) {
    std::vector<const Candidate*> which;
    for (const auto& p : pairs) which.push_back(&p.tested);
    const TestOutcome t = a.test(a.residual_after(model), a.design_of(model, true), which, 800 + static_cast<std::uint64_t>(round), "interactions between the causes");
    std::vector<std::size_t> order(pairs.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) { return t.z[x] > t.z[y]; });
    const double cv_now = a.cv_mse(model, true, nullptr, "");
    bool added = false;
    for (std::size_t k : order) {
        const std::string cause = a.column_of(pairs[k].term.candidate).name;
        const std::string times = a.column_of(*pairs[k].term.times).name;
        // Each pair once: a later round (given a kept interaction) updates its p.
        auto record = std::find_if(out.checks.begin(), out.checks.end(), [&](const InteractionCheck& i) { return i.covariate == cause && i.times == times; });
        if (record == out.checks.end()) record = out.checks.insert(out.checks.end(), {cause, times, t.adjusted[k], false, 0.0});
        else record->p_value = t.adjusted[k];
        if (added || t.adjusted[k] > a.opt.alpha) continue;
        std::vector<Term> with_main = model;
        const bool companion = !has_linear_term(model, pairs[k].companion.candidate);
        if (companion) with_main.push_back(pairs[k].companion);
        const double cv = a.cv_mse(with_main, true, &pairs[k].product, "interaction");
        char line[256];
        std::snprintf(line, sizeof line, "interaction '%s' x '%s': p = %.4g (family-wise over %zu pairs); CV %s %.5f -> %.5f: %s", cause.c_str(), times.c_str(),
                      t.adjusted[k], pairs.size(), a.loss_name(), cv_now, cv, cv < cv_now ? "kept" : "not worth a term");
        out.log.push_back(line);
        if (cv < cv_now) {
            reshape_beside(a, model, pairs[k], out);
            if (companion) out.terms.push_back(pairs[k].companion);
            out.terms.push_back(pairs[k].term);
            record->kept = true;
            added = true;
        }
    }
    return added;
}

} // namespace

Interactions add_interactions(const Analysis& a, std::vector<Term> causes) {
    Interactions out;
    out.causes = std::move(causes);
    for (int round = 0; round < 2; ++round) {
        std::vector<Term> model = out.causes;
        model.insert(model.end(), out.terms.begin(), out.terms.end());
        std::vector<Pair> pairs = pairs_of(a, out.causes, out.terms);
        if (pairs.empty() || !add_one(a, model, pairs, round, out)) break;
    }
    // Significant first, then by p.
    std::stable_sort(out.checks.begin(), out.checks.end(),
                     [](const InteractionCheck& x, const InteractionCheck& y) { return x.kept != y.kept ? x.kept : x.p_value < y.p_value; });
    return out;
}

} // namespace ikebana::game::discrepancy
