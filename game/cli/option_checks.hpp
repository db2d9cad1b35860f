#pragma once
// Checks for numeric command-line options that CLI11's own Range lets through (NaN compares false
// with both ends, so `--angle nan` passed) or words badly (its "not in range 0 to 1.8e308").
#include <string>

#include <CLI/CLI.hpp>

namespace ikebana::game {

// The longest simulated span the integer-microsecond timeline holds with room to spare (int64 µs
// would overflow at 9.2e12 s; "1e13 s" once ran nothing and reported it as done).
inline constexpr double max_simulated_seconds = 1e12;

// A finite number in [lo, hi], in `unit` (said in the message).
CLI::Validator finite_in(double lo, double hi, const std::string& unit);
// A finite number of simulated seconds: at least one microsecond, at most max_simulated_seconds.
CLI::Validator simulated_seconds();

} // namespace ikebana::game
