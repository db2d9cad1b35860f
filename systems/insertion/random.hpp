#pragma once
// Draws from the world's RandomStream (splitmix64): deterministic, and part of the hashed state.
#include <cstdint>

#include "components/insertion.hpp"

namespace ikebana::systems::insertion {

inline std::uint64_t next_u64(components::RandomStream& s) noexcept {
    std::uint64_t z = (s.state += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

// Uniform in [0, 1).
inline double next_unit(components::RandomStream& s) noexcept {
    return static_cast<double>(next_u64(s) >> 11) * 0x1.0p-53;
}

} // namespace ikebana::systems::insertion
