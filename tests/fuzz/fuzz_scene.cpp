// libFuzzer: game::parse_scene, the reader of a user-given file, on arbitrary bytes.
#include "game/scene/scene.hpp"
#include "tests/fuzz/fuzz_target.hpp"

using namespace ikebana;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    fuzz::expect_named(game::parse_scene(fuzz::text_of(data, size), fuzz::label));
    return 0;
}
