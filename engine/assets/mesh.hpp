#pragma once
// Triangle meshes from glTF 2.0 files (tinygltf, Debian's libtinygltf). The loader checks every index
// and byte range itself before touching data, so a broken or hostile file gives an error naming the
// file and the offending element, never a crash. A mesh that cannot be loaded is replaced by the
// caller with placeholder_mesh() and a warning.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "engine/core/result.hpp"

namespace ikebana::assets {

struct MeshData {
    std::string name;
    std::vector<glm::vec3> positions;
    std::vector<glm::vec3> normals; // unit length, one per position
    std::vector<std::uint32_t> indices; // triangles
    std::size_t skipped_images = 0;     // pictures the file names: never read or decoded (a mesh here is its triangles)
};

// A petal, a leaf or a head is drawn by the hundred: more than this is a mistake (or an attack), refused.
inline constexpr std::size_t max_mesh_vertices = 1'000'000;

// The first triangle primitive of the first mesh, with POSITION and NORMAL, from a .gltf (text) or a .glb
// (binary). Before tinygltf sees it, the file must be a regular file of at most 64 MiB nesting its JSON
// no deeper than 64 levels; external buffers are read only from the file's own folder (never an absolute
// path or a ../ escape), and images are skipped, never decoded.
Result<MeshData> load_gltf_mesh(const std::filesystem::path& path);
// The same from bytes already read (`label` names them in errors); external files are refused.
Result<MeshData> parse_gltf_mesh(const std::string& bytes, const std::string& label);

// Writes a .gltf with the buffer embedded as a base64 data URI (one self-contained text file).
Result<void> write_gltf_mesh(const std::filesystem::path& path, const MeshData& mesh);
std::string gltf_text(const MeshData& mesh);

// A small octahedron, drawn where a mesh is missing or broken.
MeshData placeholder_mesh();

} // namespace ikebana::assets
