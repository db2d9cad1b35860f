#pragma once
// A small SVG chart writer for the validation report: scatter points, lines, error bars, a legend, and
// linear or logarithmic axes with readable ticks. Enough for a researcher to read a figure on its own;
// no dependency to install.
#include <string>
#include <vector>

namespace ikebana::game {

struct SvgSeries {
    std::string label;
    std::string colour;              // "#1f77b4"
    std::vector<double> x, y;
    std::vector<double> low, high;   // error bars when given (same length as y)
    bool line = false;               // joined, else points
    double radius = 2.5;
    double opacity = 0.6;
    std::string marker = "circle";   // circle, square, triangle: series that overlap stay told apart
    std::vector<std::string> labels; // a short text beside each point when given (say, its insertion)
};

struct SvgChart {
    std::string title;
    std::string x_label, y_label;
    bool log_x = false, log_y = false;
    std::vector<std::string> x_categories; // when given, x is an index into these
    std::vector<SvgSeries> series;
    std::vector<double> reference_y;       // horizontal dashed lines (say, a factor of 1)
    bool identity_line = false;            // y = x (model against data)
};

std::string render_svg(const SvgChart& chart, int width = 640, int height = 420);

} // namespace ikebana::game
