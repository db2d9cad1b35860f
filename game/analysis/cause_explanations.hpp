#pragma once
// A researcher's sentence for each cause: what the fitted term says in numbers, and for the standard
// columns of the measured-data format the physical reading (the unknown ones get the numbers only).
#include <string>

#include "game/analysis/discrepancy_analysis.hpp"

namespace ikebana::game {

std::string explain_cause(const Cause& cause);

} // namespace ikebana::game
