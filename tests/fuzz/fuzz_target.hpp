#pragma once
// What every harness asserts besides "no crash, no hang, no sanitizer report": a reader that refuses
// an input says why, naming the input. The label each harness passes is "fuzz-input".
#include <cstdint>
#include <cstdlib>
#include <cstdio>
#include <string>
#include <string_view>

#include "engine/core/result.hpp"

namespace ikebana::fuzz {

inline constexpr const char* label = "fuzz-input";

inline std::string_view text_of(const std::uint8_t* data, std::size_t size) {
    return {reinterpret_cast<const char*>(data), size};
}

// A refusal must name the file; anything else is a finding.
template <typename T>
void expect_named(const Result<T>& result) {
    if (result) return;
    if (result.error().message.find(label) == std::string::npos) {
        std::fprintf(stderr, "refusal does not name the input: %s\n", result.error().message.c_str());
        std::abort();
    }
}

} // namespace ikebana::fuzz
