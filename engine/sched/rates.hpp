#pragma once
// Named rates. Systems name a rate instead of a number, so that "render at 60 Hz" is one change on the
// command line or in a scene file, and so that the paper's four rates live in one place.
#include <map>
#include <string>
#include <string_view>

#include "engine/core/result.hpp"

namespace ikebana::sched {

class RateTable {
public:
    // The paper's rates (section 2.3): force output 1 kHz, position estimation 100 Hz, position check
    // 16 Hz, stereo view 30 Hz.
    static RateTable paper_defaults();

    Result<void> define(std::string name, double hz);
    // Changes an existing rate; unknown names and values that are not finite and > 0 are refused.
    Result<void> set(std::string_view name, double hz);
    // "name=hz", as given on the command line.
    Result<void> set_from_string(std::string_view assignment);

    [[nodiscard]] bool contains(std::string_view name) const { return hz_.find(std::string(name)) != hz_.end(); }
    [[nodiscard]] double hz(std::string_view name) const { return hz_.at(std::string(name)); }
    [[nodiscard]] const std::map<std::string, double>& all() const noexcept { return hz_; }
    [[nodiscard]] std::string names() const;

private:
    std::map<std::string, double> hz_;
};

// Largest rate the integer-microsecond timeline can represent faithfully.
inline constexpr double max_rate_hz = 100'000.0;
// Smallest: the schedule counts rates in whole millihertz, and a rate that rounds to zero of them
// would divide by zero when due times are computed.
inline constexpr double min_rate_hz = 0.001;

} // namespace ikebana::sched
