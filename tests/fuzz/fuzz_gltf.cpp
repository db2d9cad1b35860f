// libFuzzer: a mesh file a designer downloads, glTF text or binary GLB.
#include <string>

#include "engine/assets/mesh.hpp"
#include "tests/fuzz/fuzz_target.hpp"

using namespace ikebana;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    fuzz::expect_named(assets::parse_gltf_mesh(std::string(fuzz::text_of(data, size)), fuzz::label));
    return 0;
}
