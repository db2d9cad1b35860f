// libFuzzer: the validation report's charts (game::render_svg) on arbitrary finite data. The bytes are
// read as doubles (denormals, one value, ranges of 1e-300 or 1e300, ends near +-DBL_MAX all come up);
// the chart must end (libFuzzer's -timeout catches a hang) and hold no NaN or infinity in its numbers.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "game/analysis/svg_plot.hpp"
#include "tests/fuzz/fuzz_target.hpp"

using namespace ikebana;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size < 1) return 0;
    game::SvgChart chart;
    chart.log_x = (data[0] & 1) != 0;
    chart.log_y = (data[0] & 2) != 0;
    chart.identity_line = (data[0] & 4) != 0;
    game::SvgSeries s;
    s.line = (data[0] & 8) != 0;
    for (std::size_t at = 1; at + 16 <= size && s.x.size() < 64; at += 16) {
        double x = 0.0;
        double y = 0.0;
        std::memcpy(&x, data + at, 8);
        std::memcpy(&y, data + at + 8, 8);
        if (!std::isfinite(x) || !std::isfinite(y)) continue; // the report's data is finite
        s.x.push_back(x);
        s.y.push_back(y);
    }
    chart.series.push_back(s);
    const std::string svg = game::render_svg(chart);
    if (svg.find("nan") != std::string::npos || svg.find("inf") != std::string::npos) {
        std::fprintf(stderr, "a chart with a non-finite number in it\n");
        std::abort();
    }
    return 0;
}
