#pragma once
#include <string>

#include "engine/sched/clocks.hpp"
#include "game/world/world.hpp"

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
    double fell_at_s = 0.0;
    bool yielded = false;            // the pins gave way at least once (the moments then follow)
    double yield_holding_nm = 0.0;
    double yield_gravity_nm = 0.0;
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
[[nodiscard]] std::string format_summary(const WorldSummary& s, double seconds);
// After a real-time run: each lane's wake-up lateness and tick time, and the 1 kHz systems' lateness
// and missed deadlines.
[[nodiscard]] std::string format_realtime_report(const World& world, const std::vector<sched::LaneReport>& reports);

} // namespace ikebana::game
