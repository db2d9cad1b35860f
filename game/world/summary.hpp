#pragma once
#include <string>

#include "engine/sched/clocks.hpp"
#include "game/world/world.hpp"
#include "systems/insertion/deterioration.hpp"

namespace ikebana::game {

struct FlowerSummary {
    std::string species;
    std::uint32_t insertions = 0;
    bool broken = false;
    bool in_kenzan = false;
    std::size_t pins = 0;
    double depth_m = 0.0;
    double resistance_n = 0.0;
    double holding_moment_nm = 0.0;
    double gravity_moment_nm = 0.0;
    bool fallen = false;
    components::FallReason fall_reason = components::FallReason::none;
    double fell_at_s = 0.0;
    bool yielded = false;            // the pins gave way at least once (the moments then follow)
    double yield_holding_nm = 0.0;
    double yield_gravity_nm = 0.0;
    double elastic_j = 0.0;
    // What its springs would store with every joint bent half a turn and every segment stretched
    // by a tenth: no real stem holds more, so more means the integration has left its range.
    double elastic_ceiling_j = 0.0;
};

struct WorldSummary {
    std::vector<FlowerSummary> flower_states;
    std::size_t flowers = 0;
    std::size_t active_parts = 0;
    std::size_t passive_parts = 0;
    std::size_t inactive_parts = 0;
    std::size_t kenzan_pins = 0;
    std::size_t hands = 0;
    std::size_t contacts = 0;
    double kinetic_j = 0.0;
    double elastic_j = 0.0;
    double gravitational_j = 0.0;
    double highest_point_m = 0.0;
    std::uint64_t frames_received = 0;
};

[[nodiscard]] WorldSummary summarize(World& world);
// The haptic rate below which a flower's stiffness makes the results wrong: its stem's stiffest
// joint rings at f = sqrt(k / (m l^2)) / 2 pi, and the implicit step, linearised about its start,
// flattens or pumps the stem once a step spans more than 25 of those periods (measured: the cherry
// branch, ringing at 4.2 kHz, went wrong below about 145 Hz; the sunflower's holding moment
// drifted 20 % at 300 Hz and went negative at 100 Hz).
inline constexpr double periods_per_step_limit = 25.0;
// One sentence per thing the run would otherwise get wrong without a word: a species whose stiffness
// the haptic rate is too low for (none at the paper's 1 kHz), and a covariate an extended species reads
// that the scene's environment (or --env) does not set, with the value taken instead.
[[nodiscard]] std::vector<std::string> startup_warnings(World& world);
// The sentence for one such covariate: what is read, the value used, how to set it.
[[nodiscard]] std::string missing_covariate_sentence(const std::string& species, const systems::insertion::MissingCovariate& missing);
[[nodiscard]] std::string format_summary(const WorldSummary& s, double seconds);
// After a real-time run: each lane's wake-up lateness and tick time, and the 1 kHz systems' lateness
// and missed deadlines.
[[nodiscard]] std::string format_realtime_report(const World& world, const std::vector<sched::LaneReport>& reports);

} // namespace ikebana::game
