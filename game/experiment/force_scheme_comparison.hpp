#pragma once
// Runs one scene's scripted session under both force schemes (full rate; the paper's 16 Hz check,
// 100 Hz estimate, reused ten times) and measures, per hand, what the device would have received:
// the largest force jump from one 1 kHz tick to the next (a discontinuity the hand feels as a knock),
// its 99th percentile, and the lag of the paper scheme behind the full-rate force (the shift that
// best aligns the two signals).
#include <string>
#include <vector>

#include "engine/core/result.hpp"

namespace ikebana::game {

struct SchemeFigures {
    double max_jump_n = 0.0;
    double p99_jump_n = 0.0;
    double rms_error_n = 0.0; // against the full-rate force at the same tick
};

struct ForceSchemeComparison {
    int hand = 0;
    SchemeFigures full_rate;
    SchemeFigures paper;
    double paper_lag_ms = 0.0;
    double mean_force_n = 0.0;
};

Result<std::vector<ForceSchemeComparison>> compare_force_schemes(const std::string& scene_file, double seconds);
std::string format_force_comparison(const std::vector<ForceSchemeComparison>& result);

} // namespace ikebana::game
