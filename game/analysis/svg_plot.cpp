#include "game/analysis/svg_plot.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

namespace ikebana::game {

namespace {

std::string escape(const std::string& text) {
    std::string out;
    for (char c : text) {
        if (c == '<') out += "&lt;";
        else if (c == '>') out += "&gt;";
        else if (c == '&') out += "&amp;";
        else if (c == '"') out += "&quot;";
        else out += c;
    }
    return out;
}

std::string number(double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%.4g", v);
    return text;
}

// An axis over any finite range: denormals, one value, a range of 1e-300 or 1e300, ends near
// +-DBL_MAX. Every loop is counted, not stepped by a floating value that may not move (a step of a
// denormal's size, or one lost against a value of 1e300, looped for ever).
struct Axis {
    static constexpr int most_ticks = 12;
    double lo = 0.0, hi = 1.0;
    bool log = false;
    double to_unit(double v) const {
        const double a = log ? std::log10(std::max(v, 1e-300)) : v;
        const double l = log ? std::log10(std::max(lo, 1e-300)) : lo;
        const double h = log ? std::log10(std::max(hi, 1e-300)) : hi;
        // Halves first: h - l of two values near +-DBL_MAX overflows.
        const double width = 0.5 * h - 0.5 * l;
        if (!(width > 0.0) || !std::isfinite(width)) return 0.5;
        const double u = (0.5 * a - 0.5 * l) / width;
        return std::isfinite(u) ? u : 0.5;
    }
    std::vector<double> ticks() const {
        std::vector<double> out;
        if (!std::isfinite(lo) || !std::isfinite(hi) || !(hi >= lo)) return out;
        if (log && lo > 0.0) {
            // Decades from the one at or below lo, normal numbers only (10^-307 and up); at most
            // most_ticks of them, every k-th decade when the range is wider.
            const int first = std::max(static_cast<int>(std::floor(std::log10(lo))), -307);
            const int last = std::min(static_cast<int>(std::ceil(std::log10(hi))), 308);
            const int every = std::max(1, (last - first) / most_ticks + 1);
            for (int e = first; e <= last; e += every) {
                static constexpr double steps[] = {1.0, 2.0, 5.0};
                for (int k = 0; k < (every == 1 ? 3 : 1); ++k) {
                    const double t = steps[k] * std::pow(10.0, e);
                    if (std::isfinite(t) && t >= lo * 0.9999 && t <= hi * 1.0001) out.push_back(t);
                }
            }
            if (out.size() >= 3) return out;
            // Less than a 1-2-5 step wide: evenly stepped round numbers inside (a log axis reads them
            // as well), never the range's own odd ends.
            Axis linear = *this;
            linear.log = false;
            return linear.ticks();
        }
        const double span = 0.5 * hi - 0.5 * lo; // half the span: the whole may overflow
        if (!(span > 0.0)) {
            out.push_back(lo); // one value: one tick at it
            return out;
        }
        const double raw = span / 2.5;             // the span over 5
        const double magnitude = std::pow(10.0, std::floor(std::log10(raw)));
        double step = magnitude;
        for (double m : {1.0, 2.0, 2.5, 5.0, 10.0}) {
            if (m * magnitude >= raw) {
                step = m * magnitude;
                break;
            }
        }
        const double first = std::ceil(lo / step) * step;
        // A step too small to tell apart from the values it is added to (a denormal step, or the
        // magnitude of 10^-308 that one rounds to): the two ends only.
        if (!(step > 0.0) || !std::isfinite(step) || !std::isfinite(first) || first + step == first) {
            out.push_back(lo);
            out.push_back(hi);
            return out;
        }
        for (int i = 0; i <= most_ticks; ++i) {
            const double t = first + static_cast<double>(i) * step;
            if (!std::isfinite(t) || t > hi + 1e-9 * span) break;
            out.push_back(std::abs(t) < 1e-12 * span ? 0.0 : t);
        }
        return out;
    }
};

Axis fit_axis(std::vector<double> values, bool log) {
    values.erase(std::remove_if(values.begin(), values.end(), [&](double v) { return !std::isfinite(v) || (log && v <= 0.0); }),
                 values.end());
    Axis a;
    a.log = log;
    if (values.empty()) return a;
    const auto [mn, mx] = std::minmax_element(values.begin(), values.end());
    a.lo = *mn;
    a.hi = *mx;
    if (log) {
        a.lo /= 1.08;
        a.hi *= 1.08;
    } else {
        // A pad of 6 % each side, or (one value) 10 % of it, or 1 near zero; halves so that the span of
        // values near +-DBL_MAX does not overflow, and ends that stay finite.
        const double half_span = 0.5 * a.hi - 0.5 * a.lo;
        const double pad = half_span > 0.0 ? 0.12 * half_span : std::max(1.0, std::abs(a.lo) * 0.1);
        const double lo = a.lo - pad;
        const double hi = a.hi + pad;
        a.lo = std::isfinite(lo) ? lo : a.lo;
        a.hi = std::isfinite(hi) ? hi : a.hi;
    }
    return a;
}

// One point's marker, centred at (x, y).
std::string marker(const SvgSeries& s, double x, double y) {
    std::ostringstream o;
    const double r = s.radius;
    const std::string paint = "fill=\"" + s.colour + "\" fill-opacity=\"" + number(s.opacity) + "\"";
    if (s.marker == "square") {
        o << "<rect x=\"" << x - r << "\" y=\"" << y - r << "\" width=\"" << 2 * r << "\" height=\"" << 2 * r << "\" " << paint << "/>";
    } else if (s.marker == "triangle") {
        o << "<polygon points=\"" << x << ',' << y - 1.2 * r << ' ' << x - 1.1 * r << ',' << y + 0.8 * r << ' ' << x + 1.1 * r << ',' << y + 0.8 * r << "\" "
          << paint << "/>";
    } else {
        o << "<circle cx=\"" << x << "\" cy=\"" << y << "\" r=\"" << r << "\" " << paint << "/>";
    }
    return o.str();
}

} // namespace

std::string render_svg(const SvgChart& chart, int width, int height) {
    const double left = 70, right = 20, top = 40, bottom = 60;
    const double pw = width - left - right, ph = height - top - bottom;
    std::vector<double> xs, ys;
    for (const auto& s : chart.series) {
        xs.insert(xs.end(), s.x.begin(), s.x.end());
        ys.insert(ys.end(), s.y.begin(), s.y.end());
        ys.insert(ys.end(), s.low.begin(), s.low.end());
        ys.insert(ys.end(), s.high.begin(), s.high.end());
    }
    ys.insert(ys.end(), chart.reference_y.begin(), chart.reference_y.end());
    if (chart.identity_line) {
        const std::vector<double> both = [&] {
            std::vector<double> b = xs;
            b.insert(b.end(), ys.begin(), ys.end());
            return b;
        }();
        xs = ys = both;
    }
    Axis ax = fit_axis(xs, chart.log_x && chart.x_categories.empty());
    Axis ay = fit_axis(ys, chart.log_y);
    if (!chart.x_categories.empty()) {
        ax.lo = -0.5;
        ax.hi = static_cast<double>(chart.x_categories.size()) - 0.5;
    }
    auto px = [&](double v) { return left + ax.to_unit(v) * pw; };
    auto py = [&](double v) { return top + (1.0 - ay.to_unit(v)) * ph; };
    std::ostringstream o;
    o << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << width << "\" height=\"" << height << "\" viewBox=\"0 0 " << width << ' '
      << height << "\" font-family=\"sans-serif\" font-size=\"12\">\n";
    o << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
    o << "<text x=\"" << width / 2 << "\" y=\"22\" text-anchor=\"middle\" font-size=\"14\">" << escape(chart.title) << "</text>\n";
    o << "<rect x=\"" << left << "\" y=\"" << top << "\" width=\"" << pw << "\" height=\"" << ph << "\" fill=\"none\" stroke=\"#444\"/>\n";
    for (double t : ay.ticks()) {
        o << "<line x1=\"" << left << "\" x2=\"" << left + pw << "\" y1=\"" << py(t) << "\" y2=\"" << py(t) << "\" stroke=\"#eee\"/>";
        o << "<text x=\"" << left - 6 << "\" y=\"" << py(t) + 4 << "\" text-anchor=\"end\">" << number(t) << "</text>\n";
    }
    if (chart.x_categories.empty()) {
        for (double t : ax.ticks()) {
            o << "<line y1=\"" << top << "\" y2=\"" << top + ph << "\" x1=\"" << px(t) << "\" x2=\"" << px(t) << "\" stroke=\"#eee\"/>";
            o << "<text x=\"" << px(t) << "\" y=\"" << top + ph + 16 << "\" text-anchor=\"middle\">" << number(t) << "</text>\n";
        }
    } else {
        for (std::size_t k = 0; k < chart.x_categories.size(); ++k) {
            o << "<text x=\"" << px(static_cast<double>(k)) << "\" y=\"" << top + ph + 16 << "\" text-anchor=\"middle\">"
              << escape(chart.x_categories[k]) << "</text>\n";
        }
    }
    o << "<text x=\"" << left + pw / 2 << "\" y=\"" << height - 14 << "\" text-anchor=\"middle\">" << escape(chart.x_label) << "</text>\n";
    o << "<text transform=\"translate(16," << top + ph / 2 << ") rotate(-90)\" text-anchor=\"middle\">" << escape(chart.y_label) << "</text>\n";
    for (double r : chart.reference_y) {
        o << "<line x1=\"" << left << "\" x2=\"" << left + pw << "\" y1=\"" << py(r) << "\" y2=\"" << py(r)
          << "\" stroke=\"#888\" stroke-dasharray=\"5,4\"/>\n";
    }
    if (chart.identity_line) {
        o << "<line x1=\"" << px(ax.lo) << "\" y1=\"" << py(ax.lo) << "\" x2=\"" << px(ax.hi) << "\" y2=\"" << py(ax.hi)
          << "\" stroke=\"#888\" stroke-dasharray=\"5,4\"/>\n";
    }
    o << "<g>\n";
    for (const auto& s : chart.series) {
        if (s.line && s.x.size() > 1) {
            o << "<polyline fill=\"none\" stroke=\"" << s.colour << "\" stroke-width=\"2\" points=\"";
            for (std::size_t i = 0; i < s.x.size(); ++i) o << px(s.x[i]) << ',' << py(s.y[i]) << ' ';
            o << "\"/>\n";
        }
        for (std::size_t i = 0; i < s.x.size(); ++i) {
            if (i < s.low.size() && i < s.high.size()) {
                o << "<line x1=\"" << px(s.x[i]) << "\" x2=\"" << px(s.x[i]) << "\" y1=\"" << py(s.low[i]) << "\" y2=\"" << py(s.high[i])
                  << "\" stroke=\"" << s.colour << "\" stroke-width=\"1.5\"/>";
            }
            if (!s.line || s.radius > 0.0) o << marker(s, px(s.x[i]), py(s.y[i]));
            if (i < s.labels.size() && !s.labels[i].empty()) {
                o << "<text x=\"" << px(s.x[i]) + s.radius + 2 << "\" y=\"" << py(s.y[i]) + 4 << "\" font-size=\"9\" fill=\"" << s.colour << "\">"
                  << escape(s.labels[i]) << "</text>";
            }
        }
        o << "\n";
    }
    o << "</g>\n";
    double ly = top + 14;
    for (const auto& s : chart.series) {
        if (s.label.empty()) continue;
        if (s.line && s.radius <= 0.0) {
            o << "<line x1=\"" << left + 9 << "\" x2=\"" << left + 21 << "\" y1=\"" << ly - 4 << "\" y2=\"" << ly - 4 << "\" stroke=\"" << s.colour
              << "\" stroke-width=\"2\"/>";
        } else {
            SvgSeries key = s;
            key.radius = 4.5;
            key.opacity = 1.0;
            o << marker(key, left + 15, ly - 4);
        }
        o << "<text x=\"" << left + 26 << "\" y=\"" << ly << "\">" << escape(s.label) << "</text>\n";
        ly += 16;
    }
    o << "</svg>\n";
    return o.str();
}

} // namespace ikebana::game
