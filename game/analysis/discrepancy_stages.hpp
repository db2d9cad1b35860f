#pragma once
// The discrepancy analysis' stages, in the order run() calls them (discrepancy_analysis.hpp says what
// each decides and why): screen every covariate, select terms forward, eliminate them backward, add
// interactions between the causes, fit the final model. Each takes what the stages before it found and
// returns what it found, with the lines it adds to the report.
#include <cstdint>
#include <vector>

#include <Eigen/Dense>

#include "components/insertion.hpp"
#include "game/analysis/discrepancy_tools.hpp"

namespace ikebana::game::discrepancy {

// Every covariate against the baseline residual, and the overall level on its own.
struct Screening {
    TestOutcome first;                            // every candidate against the baseline residual
    std::vector<CovariateDiagnostic> diagnostics; // per candidate, in the file's order
    Calibration calibration;                      // the level's p-value and whether it is kept
    Log log;
};
Screening screen(const Analysis& a);

// Terms accepted one at a time, each significant given those before it and lowering the
// cross-validated error.
struct Selection {
    std::vector<Term> terms;
    std::vector<std::size_t> remaining;  // the candidates not accepted
    std::vector<double> given_model_p;   // per candidate: family-wise, given the last model it was tested against
    bool tested_final_model = false;     // the remaining candidates were last tested given exactly `terms`
    Log log;
};
Selection select_forward(const Analysis& a, const TestOutcome& first);

// The accepted terms that still hold given all the others.
struct Elimination {
    std::vector<Term> terms;
    std::vector<double> kept_p;        // per term: given all the others, Holm-adjusted over the terms
    std::vector<double> given_model_p; // per candidate: family-wise, given the final model
    Log log;
};
Elimination eliminate_backward(const Analysis& a, const Selection& forward);

// Kept causes whose effect changes with another numeric column.
struct Interactions {
    std::vector<Term> causes;             // the kept terms; one with an interaction re-shaped beside it
    std::vector<Term> terms;              // per kept pair: the other column's linear term (unless the model has it), then the product
    std::vector<InteractionCheck> checks; // every pair tested, significant first, then by p
    Log log;
};
Interactions add_interactions(const Analysis& a, std::vector<Term> causes);

// The extended model fitted on every row, its causes' effects with flower-bootstrap intervals, and its
// held-out fit.
struct FinalFit {
    bool extended = false;                                // a level or a term is kept
    Eigen::VectorXd fitted;                               // log factor per row, in sample
    Eigen::VectorXd oof;                                  // per row, from the fold that held the row out
    std::vector<components::DeteriorationTerm> extension; // exp(sum) multiplies the force; empty: none
    std::vector<Cause> causes;                            // by importance
    std::vector<InteractionCheck> checks;                 // the kept pairs with their coefficients
    Calibration calibration;                              // with the fitted level and its interval
};
FinalFit fit_final(const Analysis& a, Interactions interactions, const std::vector<double>& kept_p, Calibration calibration);

} // namespace ikebana::game::discrepancy
