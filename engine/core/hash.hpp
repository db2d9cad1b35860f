#pragma once
// State hashing: a 64-bit hash over plain data, used to prove that two runs of the deterministic clock
// produced a bit-identical world. Floating-point values are hashed by their bit pattern on purpose: the
// point is to detect any difference at all, including -0 against +0.
//
// Components are plain aggregates, so they are hashed field by field without any per-type code: the
// number of fields is found at compile time and the fields are reached with a structured binding.
// A type that is not an aggregate can provide `void hash_append(StateHasher&, const T&)` found by ADL.
#include <array>
#include <bit>
#include <cstdint>
#include <cstring>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

namespace ikebana {

class StateHasher {
public:
    // FNV-1a over 8-byte words (then the tail bytes): the same detect-any-change property at an
    // eighth of the multiplications.
    void bytes(const void* data, std::size_t size) noexcept {
        const auto* p = static_cast<const unsigned char*>(data);
        std::size_t i = 0;
        for (; i + 8 <= size; i += 8) {
            std::uint64_t word;
            std::memcpy(&word, p + i, 8);
            state_ = (state_ ^ word) * 0x100000001b3ull;
        }
        for (; i < size; ++i) state_ = (state_ ^ p[i]) * 0x100000001b3ull;
    }
    template <typename T>
        requires std::is_arithmetic_v<T> || std::is_enum_v<T>
    void scalar(T value) noexcept {
        bytes(&value, sizeof value);
    }
    [[nodiscard]] std::uint64_t digest() const noexcept {
        // Final avalanche (splitmix64) so that nearby states give unrelated digests.
        std::uint64_t z = state_ + 0x9e3779b97f4a7c15ull;
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
        return z ^ (z >> 31);
    }

private:
    std::uint64_t state_ = 0xcbf29ce484222325ull; // FNV-1a offset basis
};

namespace detail {

struct any_field {
    // Declared only: used in unevaluated brace-initialisation to count an aggregate's fields.
    template <typename T>
    operator T&() const noexcept;
    template <typename T>
    operator T&&() const noexcept;
};

template <typename T, std::size_t... I>
constexpr bool brace_constructible(std::index_sequence<I...>) {
    return requires { T{(void(I), any_field{})...}; };
}

template <typename T, std::size_t N = 16>
constexpr std::size_t field_count() {
    if constexpr (N == 0) {
        return 0;
    } else if constexpr (brace_constructible<T>(std::make_index_sequence<N>{})) {
        return N;
    } else {
        return field_count<T, N - 1>();
    }
}

template <typename T>
concept has_adl_hash_append = requires(StateHasher& h, const T& v) { hash_append(h, v); };

} // namespace detail

template <typename T>
void hash_value(StateHasher& h, const T& value);

namespace detail {

template <typename T, typename F>
void for_each_field(const T& v, F&& f) {
    constexpr std::size_t n = field_count<T>();
    // clang-format off
    if constexpr (n == 0) {}
    else if constexpr (n == 1) { const auto& [a] = v; f(a); }
    else if constexpr (n == 2) { const auto& [a, b] = v; f(a); f(b); }
    else if constexpr (n == 3) { const auto& [a, b, c] = v; f(a); f(b); f(c); }
    else if constexpr (n == 4) { const auto& [a, b, c, d] = v; f(a); f(b); f(c); f(d); }
    else if constexpr (n == 5) { const auto& [a, b, c, d, e] = v; f(a); f(b); f(c); f(d); f(e); }
    else if constexpr (n == 6) { const auto& [a, b, c, d, e, g] = v; f(a); f(b); f(c); f(d); f(e); f(g); }
    else if constexpr (n == 7) { const auto& [a, b, c, d, e, g, i] = v; f(a); f(b); f(c); f(d); f(e); f(g); f(i); }
    else if constexpr (n == 8) { const auto& [a, b, c, d, e, g, i, j] = v; f(a); f(b); f(c); f(d); f(e); f(g); f(i); f(j); }
    else if constexpr (n == 9) { const auto& [a, b, c, d, e, g, i, j, k] = v; f(a); f(b); f(c); f(d); f(e); f(g); f(i); f(j); f(k); }
    else if constexpr (n == 10) { const auto& [a, b, c, d, e, g, i, j, k, l] = v; f(a); f(b); f(c); f(d); f(e); f(g); f(i); f(j); f(k); f(l); }
    else if constexpr (n == 11) { const auto& [a, b, c, d, e, g, i, j, k, l, m] = v; f(a); f(b); f(c); f(d); f(e); f(g); f(i); f(j); f(k); f(l); f(m); }
    else if constexpr (n == 12) { const auto& [a, b, c, d, e, g, i, j, k, l, m, o] = v; f(a); f(b); f(c); f(d); f(e); f(g); f(i); f(j); f(k); f(l); f(m); f(o); }
    else if constexpr (n == 13) { const auto& [a, b, c, d, e, g, i, j, k, l, m, o, p] = v; f(a); f(b); f(c); f(d); f(e); f(g); f(i); f(j); f(k); f(l); f(m); f(o); f(p); }
    else if constexpr (n == 14) { const auto& [a, b, c, d, e, g, i, j, k, l, m, o, p, q] = v; f(a); f(b); f(c); f(d); f(e); f(g); f(i); f(j); f(k); f(l); f(m); f(o); f(p); f(q); }
    else if constexpr (n == 15) { const auto& [a, b, c, d, e, g, i, j, k, l, m, o, p, q, r] = v; f(a); f(b); f(c); f(d); f(e); f(g); f(i); f(j); f(k); f(l); f(m); f(o); f(p); f(q); f(r); }
    else if constexpr (n == 16) { const auto& [a, b, c, d, e, g, i, j, k, l, m, o, p, q, r, s] = v; f(a); f(b); f(c); f(d); f(e); f(g); f(i); f(j); f(k); f(l); f(m); f(o); f(p); f(q); f(r); f(s); }
    // clang-format on
    else static_assert(n <= 16, "components with more than 16 fields need an ADL hash_append");
}

template <typename T> struct is_vector : std::false_type {};
template <typename T, typename A> struct is_vector<std::vector<T, A>> : std::true_type {};
template <typename T> struct is_std_array : std::false_type {};
template <typename T, std::size_t N> struct is_std_array<std::array<T, N>> : std::true_type {};
template <typename T> struct is_optional : std::false_type {};
template <typename T> struct is_optional<std::optional<T>> : std::true_type {};
template <typename T> struct is_map : std::false_type {};
template <typename K, typename V, typename C, typename A> struct is_map<std::map<K, V, C, A>> : std::true_type {};
template <typename T> struct is_pair : std::false_type {};
template <typename A, typename B> struct is_pair<std::pair<A, B>> : std::true_type {};
template <typename T> struct is_glm : std::false_type {};
template <glm::length_t L, typename T, glm::qualifier Q> struct is_glm<glm::vec<L, T, Q>> : std::true_type {};
template <glm::length_t C, glm::length_t R, typename T, glm::qualifier Q> struct is_glm<glm::mat<C, R, T, Q>> : std::true_type {};
template <typename T, glm::qualifier Q> struct is_glm<glm::qua<T, Q>> : std::true_type {};

} // namespace detail

template <typename T>
void hash_value(StateHasher& h, const T& value) {
    using U = std::remove_cvref_t<T>;
    if constexpr (detail::has_adl_hash_append<U>) {
        hash_append(h, value);
    } else if constexpr (std::is_arithmetic_v<U> || std::is_enum_v<U>) {
        h.scalar(value);
    } else if constexpr (std::is_same_v<U, std::string> || std::is_same_v<U, std::string_view>) {
        h.scalar(value.size());
        h.bytes(value.data(), value.size());
    } else if constexpr (detail::is_glm<U>::value) {
        // GLM types are tightly packed arrays of their scalar type.
        h.bytes(&value, sizeof(U));
    } else if constexpr (detail::is_vector<U>::value || detail::is_std_array<U>::value || detail::is_map<U>::value) {
        h.scalar(static_cast<std::uint64_t>(value.size()));
        for (const auto& element : value) hash_value(h, element);
    } else if constexpr (detail::is_pair<U>::value) {
        hash_value(h, value.first);
        hash_value(h, value.second);
    } else if constexpr (detail::is_optional<U>::value) {
        h.scalar(value.has_value());
        if (value) hash_value(h, *value);
    } else if constexpr (std::is_aggregate_v<U>) {
        detail::for_each_field(value, [&h](const auto& field) { hash_value(h, field); });
    } else {
        static_assert(sizeof(U) == 0, "no way to hash this type: make it an aggregate or give it hash_append");
    }
}

} // namespace ikebana
