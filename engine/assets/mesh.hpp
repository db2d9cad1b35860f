#pragma once
// Triangle meshes from glTF 2.0 files (tinygltf, Debian's libtinygltf). The loader checks every index
// and byte range itself before touching data, so a broken or hostile file gives an error naming the
// file and the offending element, never a crash. A mesh that cannot be loaded is replaced by the
// caller with placeholder_mesh() and a warning.
#include <compare>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

#include "engine/assets/image.hpp"
#include "engine/core/result.hpp"

namespace ikebana::assets {

// How a picture is sampled (a glTF sampler): nearest or linear, and what lies past its edges.
struct TextureSampling {
    enum class Wrap { repeat, clamp, mirror };
    bool nearest_magnification = false; // magFilter NEAREST: texels stay square up close
    bool nearest_minification = false;  // minFilter NEAREST*: no blending between texels from afar
    Wrap wrap_u = Wrap::repeat, wrap_v = Wrap::repeat;
    bool operator==(const TextureSampling&) const = default;
    auto operator<=>(const TextureSampling&) const = default;
};

// How a part of a mesh is coloured and lit: glTF's metallic-roughness material, as far as the shading
// uses it (the factors; a metallic-roughness texture is not read).
struct MeshMaterial {
    std::string name;
    glm::vec4 base_colour{1.0f};       // linear RGBA, times the base colour texture
    int base_colour_image = -1;        // into MeshData::images; -1: none
    TextureSampling base_colour_sampling;
    int normal_image = -1;             // a tangent-space normal map; -1: none
    TextureSampling normal_sampling;
    float normal_scale = 1.0f;
    float metallic = 0.0f;             // 0..1; the default material's 0 (a glTF material's own default is 1)
    float roughness = 1.0f;            // 0..1
    // Leaves cut out of a quad: fragments whose alpha is below alpha_cutoff are not drawn. glTF's
    // BLEND is drawn as MASK at 0.5 (petals are not sorted back to front). Negative: opaque.
    float alpha_cutoff = -1.0f;
};

// A run of triangles drawn with one material (a glTF primitive).
struct MeshPart {
    std::uint32_t first_index = 0;
    std::uint32_t index_count = 0;
    int material = -1; // into MeshData::materials; -1: the default (white, rough, opaque)
};

struct MeshData {
    std::string name;
    std::vector<glm::vec3> positions;
    std::vector<glm::vec3> normals;   // unit length, one per position
    std::vector<glm::vec2> uvs;       // TEXCOORD_0, one per position, or empty (no texture can apply)
    std::vector<glm::vec4> tangents;  // xyz unit, w the bitangent's sign; one per position, or empty
    std::vector<std::uint32_t> indices; // triangles
    // Parts in order, covering the indices; empty: the whole mesh is one part with the default material.
    std::vector<MeshPart> parts;
    std::vector<MeshMaterial> materials;
    std::vector<DecodedImage> images;
};

// A petal, a leaf or a head is drawn by the hundred: more than this is a mistake (or an attack), refused.
inline constexpr std::size_t max_mesh_vertices = 1'000'000;

// Every triangle primitive of the default scene's nodes (every root node when there is no scene), each
// moved by its node's transform (a matrix, or translation, rotation and scale, down the hierarchy), with
// POSITION and NORMAL (required), TEXCOORD_0 and TANGENT when present, its material and the pictures it
// names, from a .gltf (text, with files beside it or data: URIs) or a .glb (binary). Points and lines are
// left out. Before tinygltf sees it, the file must be a regular file of at most 64 MiB nesting its JSON no
// deeper than 64 levels; buffers and pictures are read only from the file's own folder (never an
// absolute path or a ../ escape); a picture is decoded only when its header says at most 4096 a side;
// nodes must form trees (a node with two parents, or its own ancestor, is refused).
Result<MeshData> load_gltf_mesh(const std::filesystem::path& path);
// The same from bytes already read (`label` names them in errors); external files are refused.
Result<MeshData> parse_gltf_mesh(const std::string& bytes, const std::string& label);

// Writes a .gltf with the buffer embedded as a base64 data URI (one self-contained text file): the
// positions, normals and indices (what the procedural meshes have), no materials or pictures.
Result<void> write_gltf_mesh(const std::filesystem::path& path, const MeshData& mesh);
std::string gltf_text(const MeshData& mesh);

// Bytes as base64, for a data: URI.
std::string base64(std::string_view bytes);

// A small octahedron, drawn where a mesh is missing or broken.
MeshData placeholder_mesh();

} // namespace ikebana::assets
