#pragma once
// A stable, human-readable name for a type, taken from the compiler's function signature. Used where
// an order must not depend on the order in which types happened to be first used (the state hash,
// conflict reports), and in messages.
#include <string_view>

namespace ikebana {

template <typename T>
constexpr std::string_view type_name() noexcept {
    std::string_view pretty = __PRETTY_FUNCTION__;
    constexpr std::string_view key = "T = ";
    const auto start = pretty.find(key) + key.size();
    const auto end = pretty.find_first_of(";]", start);
    return pretty.substr(start, end - start);
}

} // namespace ikebana
