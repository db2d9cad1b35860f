#include "game/cli/option_checks.hpp"

#include <charconv>
#include <cmath>
#include <sstream>

#include "engine/core/number_text.hpp"

namespace ikebana::game {

namespace {
// Whole text as a finite double, or the reason it is not one.
std::string parse_finite(const std::string& text, double& value) {
    const auto* end = text.data() + text.size();
    const auto [ptr, ec] = std::from_chars(text.data(), end, value);
    if (ec == std::errc::result_out_of_range) return "'" + text + "' is out of range for a number";
    if (ec != std::errc{} || ptr != end) return "'" + text + "' is not a number";
    if (!std::isfinite(value)) return "'" + text + "' is not a finite number";
    return {};
}
} // namespace

CLI::Validator finite_in(double lo, double hi, const std::string& unit) {
    const std::string range = "[" + number_text(lo) + ", " + number_text(hi) + "]" + (unit.empty() ? "" : " " + unit);
    return CLI::Validator(
        [lo, hi, range](std::string& text) -> std::string {
            double v = 0.0;
            if (auto why = parse_finite(text, v); !why.empty()) return why + "; expected a number in " + range;
            if (v < lo || v > hi) return text + " is outside " + range;
            return {};
        },
        "in " + range);
}

CLI::Validator simulated_seconds() {
    return CLI::Validator(
        [](std::string& text) -> std::string {
            double v = 0.0;
            if (auto why = parse_finite(text, v); !why.empty()) return why + "; expected seconds, e.g. 10";
            if (v < 1e-6) return text + " s is less than the timeline's step of one microsecond";
            if (v > max_simulated_seconds) {
                return text + " s is more than the 1e12 s the microsecond timeline can hold";
            }
            return {};
        },
        "in [1e-6, 1e12] s");
}

} // namespace ikebana::game
