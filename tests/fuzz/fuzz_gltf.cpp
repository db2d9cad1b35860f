// libFuzzer: a mesh file a designer downloads, glTF text or binary GLB, and the coarse copy the
// renderer makes of whatever it reads (every index must name a vertex, every part stay in its indices).
#include <cstdlib>
#include <string>

#include "engine/assets/mesh.hpp"
#include "engine/render/mesh_lod.hpp"
#include "tests/fuzz/fuzz_target.hpp"

using namespace ikebana;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const auto mesh = assets::parse_gltf_mesh(std::string(fuzz::text_of(data, size)), fuzz::label);
    fuzz::expect_named(mesh);
    if (!mesh) return 0;
    const auto coarse = render::clustered_mesh(*mesh, 8);
    for (const auto i : coarse.indices) {
        if (i >= coarse.positions.size()) std::abort();
    }
    for (const auto& part : coarse.parts) {
        if (part.first_index > coarse.indices.size() || part.index_count > coarse.indices.size() - part.first_index) std::abort();
    }
    if (coarse.normals.size() != coarse.positions.size()) std::abort();
    return 0;
}
