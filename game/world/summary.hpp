#pragma once
#include <string>

#include "game/world/world.hpp"

namespace ikebana::game {

struct WorldSummary {
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

} // namespace ikebana::game
