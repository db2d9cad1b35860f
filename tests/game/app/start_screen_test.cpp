// The start screen's trend of a lesson's scores (issue 41): points labelled with their score and day,
// as many labels as fit and the last always, on an axis that does not flatten scores near the top.
#include <gtest/gtest.h>

#include "game/app/start_screen.hpp"

using namespace ikebana::game;

namespace {
std::vector<SessionRecord> sessions(const std::vector<double>& scores) {
    std::vector<SessionRecord> out;
    for (std::size_t i = 0; i < scores.size(); ++i) {
        SessionRecord s;
        s.started_unix_s = 1'795'000'000 + static_cast<std::int64_t>(i) * 86'400; // a day apart
        s.result.score = scores[i];
        s.kind = i == 1 ? "demonstration" : "practice";
        out.push_back(s);
    }
    return out;
}
std::vector<const SessionRecord*> pointers(const std::vector<SessionRecord>& list) {
    std::vector<const SessionRecord*> out;
    for (const auto& s : list) out.push_back(&s);
    return out;
}
} // namespace

TEST(StartScreenTrend, EachSessionIsAPointLabelledWithItsScoreAndDayAsFarAsTheyFitTheLastAlways) {
    const auto list = sessions({73.0, 86.8, 77.8, 90.3});
    const auto wide = trend_layout(pointers(list), 600.0f, 46.0f);
    ASSERT_EQ(wide.points.size(), 4u);
    EXPECT_DOUBLE_EQ(wide.floor_score, 50.0) << "at least down to 50";
    for (const auto& p : wide.points) EXPECT_TRUE(p.labelled);
    EXPECT_EQ(wide.points[0].score, "73");
    EXPECT_EQ(wide.points[3].score, "90");
    EXPECT_EQ(wide.points[0].day, "11-18");
    EXPECT_EQ(wide.points[3].day, "11-21");
    EXPECT_TRUE(wide.points[1].demonstration);
    EXPECT_FALSE(wide.points[0].demonstration);
    EXPECT_FLOAT_EQ(wide.points[0].x, 0.0f);
    EXPECT_FLOAT_EQ(wide.points[3].x, 600.0f);
    EXPECT_NEAR(wide.points[0].y, (73.0 - 50.0) / 50.0, 1e-6);
    EXPECT_GT(wide.points[3].y, wide.points[2].y) << "a higher score stands higher";

    // Narrow, the labels thin out from the last back, never closer than asked.
    const auto many = sessions(std::vector<double>(20, 80.0));
    const auto narrow = trend_layout(pointers(many), 200.0f, 46.0f);
    EXPECT_TRUE(narrow.points.back().labelled);
    float last_x = -1e9f;
    std::size_t labelled = 0;
    for (const auto& p : narrow.points) {
        if (!p.labelled) continue;
        EXPECT_GE(p.x - last_x, 46.0f);
        last_x = p.x;
        ++labelled;
    }
    EXPECT_GE(labelled, 4u);
    EXPECT_LT(labelled, 20u);
    // The axis goes to ten below the lowest score's tens (0 for a zero); one session stands in the middle.
    EXPECT_DOUBLE_EQ(trend_layout(pointers(sessions({0.0, 100.0})), 100.0f, 46.0f).floor_score, 0.0);
    EXPECT_DOUBLE_EQ(trend_layout(pointers(sessions({35.0})), 100.0f, 46.0f).floor_score, 20.0);
    const auto one = trend_layout(pointers(sessions({100.0})), 100.0f, 46.0f);
    EXPECT_DOUBLE_EQ(one.floor_score, 50.0);
    EXPECT_FLOAT_EQ(one.points[0].x, 50.0f);
    EXPECT_FLOAT_EQ(one.points[0].y, 1.0f);
}
