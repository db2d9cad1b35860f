// libFuzzer: devices::parse_woodenhaptics_profile, the reader of a user-given file, on arbitrary bytes.
#include "engine/devices/woodenhaptics.hpp"
#include "tests/fuzz/fuzz_target.hpp"

using namespace ikebana;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    fuzz::expect_named(devices::parse_woodenhaptics_profile(fuzz::text_of(data, size), fuzz::label));
    return 0;
}
