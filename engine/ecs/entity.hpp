#pragma once
// An entity is an index into the registry's slots plus the generation of that slot. Destroying an
// entity bumps its slot's generation, so every handle still held to it stops being valid and can never
// be mistaken for the entity that later reuses the slot.
#include <compare>
#include <cstdint>
#include <functional>

namespace ikebana::ecs {

struct Entity {
    std::uint32_t index = ~0u;
    std::uint32_t generation = 0;

    [[nodiscard]] constexpr bool is_null() const noexcept { return index == ~0u; }
    [[nodiscard]] constexpr std::uint64_t bits() const noexcept {
        return (std::uint64_t{generation} << 32) | index;
    }
    friend constexpr auto operator<=>(const Entity&, const Entity&) = default;
};

inline constexpr Entity null_entity{};

} // namespace ikebana::ecs

template <>
struct std::hash<ikebana::ecs::Entity> {
    std::size_t operator()(const ikebana::ecs::Entity& e) const noexcept { return std::hash<std::uint64_t>{}(e.bits()); }
};
