#include <gtest/gtest.h>

#include "game/experiment/force_scheme_comparison.hpp"

using namespace ikebana::game;

// The paper's multi-rate scheme (16 Hz check, 100 Hz estimate, each force sent ten times) against
// forces computed every tick, on the same scripted session: the held force arrives late and in steps.
TEST(ForceSchemes, FullRateIsSmootherAndHasNoLag) {
    const auto result = compare_force_schemes(std::string(IKEBANA_ASSET_DIR) + "/scenes/arrangement.json", 6.0);
    ASSERT_TRUE(result) << result.error().message;
    ASSERT_FALSE(result->empty()) << "some hand felt something";
    for (const auto& c : *result) {
        EXPECT_GT(c.paper.p99_jump_n, 2.0 * c.full_rate.p99_jump_n) << "hand " << c.hand;
        EXPECT_GT(c.paper.max_jump_n, c.full_rate.max_jump_n);
        EXPECT_GE(c.paper_lag_ms, 20.0) << "a 16 Hz check trails by tens of milliseconds";
        EXPECT_GT(c.paper.rms_error_n, 0.0);
    }
}
