// The report's charts take any finite data and end: an axis over denormals, one value, ranges of
// 1e-300 and 1e300, ends near +-DBL_MAX, two values one rounding step apart (a denormal force once
// spun the log axis's tick loop for ever: issue 58).
#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <string>
#include <vector>

#include "game/analysis/svg_plot.hpp"

using namespace ikebana::game;

namespace {
std::string chart_of(const std::vector<double>& ys, bool log_y) {
    SvgChart chart;
    chart.log_y = log_y;
    SvgSeries s;
    for (std::size_t i = 0; i < ys.size(); ++i) {
        s.x.push_back(static_cast<double>(i));
        s.y.push_back(ys[i]);
    }
    chart.series.push_back(s);
    return render_svg(chart);
}
} // namespace

TEST(SvgPlot, AnAxisOverAnyFiniteDataEndsWithFiniteNumbersAndItsTicks) {
    const std::vector<std::vector<double>> cases{
        {355, 276, 363, 1e-323},             // the denormal that hung
        {5.0},                               // one value
        {1e-300, 2e-300, 3e-300},            // a range of 1e-300
        {-1e300, 1e300},                     // a range of 2e300
        {-DBL_MAX, DBL_MAX},                 // the widest
        {1.0, std::nextafter(1.0, 2.0)},     // one rounding step apart
        {DBL_MIN, DBL_MIN * 2},              // the smallest normal numbers
        {4.9e-324, 1e-323},                  // denormals only
    };
    for (const auto& ys : cases) {
        for (const bool log_y : {false, true}) {
            const std::string svg = chart_of(ys, log_y);
            SCOPED_TRACE(std::to_string(ys.front()) + (log_y ? " log" : " linear"));
            EXPECT_EQ(svg.find("nan"), std::string::npos);
            EXPECT_EQ(svg.find("inf"), std::string::npos);
            EXPECT_NE(svg.find("</svg>"), std::string::npos);
        }
    }
}
