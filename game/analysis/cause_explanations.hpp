#pragma once
// A researcher's sentence for each cause: what the fitted term says in numbers, and for the standard
// columns of the measured-data format the physical reading (the unknown ones get the numbers only).
#include <string>

#include "game/analysis/discrepancy_analysis.hpp"

namespace ikebana::game {

std::string explain_cause(const Cause& cause);

// The range a numeric cause's effect spans, in the data's own terms: "from 42.8 to 78.5", or for the
// insertion count "from the 1st to the 6th insertion".
std::string cause_span(const Cause& cause);

} // namespace ikebana::game
