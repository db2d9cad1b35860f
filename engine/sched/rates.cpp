#include "engine/sched/rates.hpp"

#include <charconv>
#include <cmath>
#include <sstream>
#include <string>

#include "engine/core/number_text.hpp"

namespace ikebana::sched {

namespace {
Result<void> check_hz(std::string_view name, double hz) {
    if (!std::isfinite(hz) || hz <= 0.0) {
        return make_error(ErrorCode::invalid_argument,
                          "rate '" + std::string(name) + "' must be a positive number of Hz, got " + number_text(hz));
    }
    if (hz < min_rate_hz) {
        return make_error(ErrorCode::invalid_argument, "rate '" + std::string(name) + "' of " + number_text(hz) +
                                                           " Hz is below the supported minimum of 0.001 Hz");
    }
    if (hz > max_rate_hz) {
        return make_error(ErrorCode::invalid_argument, "rate '" + std::string(name) + "' of " + number_text(hz) +
                                                           " Hz is above the supported maximum of 100000 Hz");
    }
    return {};
}
} // namespace

RateTable RateTable::paper_defaults() {
    RateTable t;
    (void)t.define("haptic", 1000.0);
    (void)t.define("position_estimate", 100.0);
    (void)t.define("position_check", 16.0);
    (void)t.define("render", 30.0);
    return t;
}

Result<void> RateTable::define(std::string name, double hz) {
    if (auto ok = check_hz(name, hz); !ok) return ok;
    hz_[std::move(name)] = hz;
    return {};
}

Result<void> RateTable::set(std::string_view name, double hz) {
    auto it = hz_.find(std::string(name));
    if (it == hz_.end()) {
        return make_error(ErrorCode::not_found, "unknown rate '" + std::string(name) + "' (known: " + names() + ")");
    }
    if (auto ok = check_hz(name, hz); !ok) return ok;
    it->second = hz;
    return {};
}

Result<void> RateTable::set_from_string(std::string_view assignment) {
    const auto eq = assignment.find('=');
    if (eq == std::string_view::npos || eq == 0) {
        return make_error(ErrorCode::invalid_argument,
                          "rate '" + std::string(assignment) + "' must look like name=hz, e.g. render=60");
    }
    const auto name = assignment.substr(0, eq);
    const auto number = std::string(assignment.substr(eq + 1));
    // Decimal only, as a person writes Hz: strtod also reads "0x10" (16) and "  60", and would take
    // what was a typo for a rate.
    double hz = 0.0;
    const auto [end, ec] = std::from_chars(number.data(), number.data() + number.size(), hz);
    if (number.empty() || ec != std::errc{} || end != number.data() + number.size()) {
        return make_error(ErrorCode::invalid_argument,
                          "rate '" + std::string(name) + "': '" + number + "' is not a number of Hz");
    }
    return set(name, hz);
}

std::string RateTable::names() const {
    std::string out;
    for (const auto& [name, hz] : hz_) {
        if (!out.empty()) out += ", ";
        out += name;
    }
    return out;
}

} // namespace ikebana::sched
