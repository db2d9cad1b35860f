#pragma once
// glTF files made by the tests themselves (nothing downloaded, nothing committed): a textured quad as a
// designer's Blender export has it (a .gltf, its picture a PNG beside it or in a data: URI, a material
// with a base colour texture) and a two-node .glb (a parent and a child node, each moving a primitive
// with a material of its own).
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/assets/files.hpp"
#include "engine/assets/mesh.hpp"
#include "engine/render/png_image.hpp"

namespace ikebana::test {

template <typename T>
void append_bytes(std::string& buffer, const std::vector<T>& values) {
    buffer.append(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T));
}

// A 2x2 picture: red, green (top row), blue, yellow (bottom row), as a PNG's bytes; with `blue_clear`
// the blue texel is fully transparent (a leaf's cut-out).
inline std::string four_colour_png(const std::filesystem::path& scratch, bool blue_clear = false) {
    render::RgbaImage img{2, 2, {255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, static_cast<std::uint8_t>(blue_clear ? 0 : 255), 255, 255, 0, 255}};
    const auto path = scratch / "four_colours.png";
    if (!render::write_png(path, img)) return {};
    auto bytes = assets::read_text_file(path);
    return bytes ? *bytes : std::string();
}

// The quad's geometry: 1 m square in the xy plane facing +z, texture coordinates over the whole
// picture (u along +x, v down -y, as glTF's picture rows run), uint16 indices. Returns the buffer and
// fills the accessors and views.
inline std::string quad_buffer(nlohmann::json& gltf) {
    const std::vector<float> positions = {-0.5f, 0.5f, 0, 0.5f, 0.5f, 0, 0.5f, -0.5f, 0, -0.5f, -0.5f, 0};
    const std::vector<float> normals = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
    const std::vector<float> uvs = {0, 0, 1, 0, 1, 1, 0, 1};
    const std::vector<std::uint16_t> indices = {0, 2, 1, 0, 3, 2};
    std::string buffer;
    append_bytes(buffer, positions);
    append_bytes(buffer, normals);
    append_bytes(buffer, uvs);
    append_bytes(buffer, indices);
    gltf["bufferViews"] = {{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", 48}},
                           {{"buffer", 0}, {"byteOffset", 48}, {"byteLength", 48}},
                           {{"buffer", 0}, {"byteOffset", 96}, {"byteLength", 32}},
                           {{"buffer", 0}, {"byteOffset", 128}, {"byteLength", 12}}};
    gltf["accessors"] = {{{"bufferView", 0}, {"componentType", 5126}, {"count", 4}, {"type", "VEC3"}, {"min", {-0.5, -0.5, 0}}, {"max", {0.5, 0.5, 0}}},
                         {{"bufferView", 1}, {"componentType", 5126}, {"count", 4}, {"type", "VEC3"}},
                         {{"bufferView", 2}, {"componentType", 5126}, {"count", 4}, {"type", "VEC2"}},
                         {{"bufferView", 3}, {"componentType", 5123}, {"count", 6}, {"type", "SCALAR"}}};
    return buffer;
}

// `folder`/quad.gltf, its picture in `folder`/four_colours.png (or a data: URI when embedded); `masked`:
// the blue texel transparent and the material's alphaMode MASK.
inline std::filesystem::path write_textured_quad(const std::filesystem::path& folder, bool embedded_picture, bool masked = false) {
    std::filesystem::create_directories(folder);
    const std::string png = four_colour_png(folder, masked);
    nlohmann::json gltf;
    gltf["asset"] = {{"version", "2.0"}, {"generator", "ikebana tests"}};
    const std::string buffer = quad_buffer(gltf);
    gltf["buffers"] = {{{"byteLength", buffer.size()}, {"uri", "data:application/octet-stream;base64," + assets::base64(buffer)}}};
    gltf["images"] = {embedded_picture ? nlohmann::json{{"uri", "data:image/png;base64," + assets::base64(png)}} : nlohmann::json{{"uri", "four_colours.png"}}};
    gltf["samplers"] = {{{"magFilter", 9728}, {"minFilter", 9728}}}; // nearest: four flat colours
    gltf["textures"] = {{{"source", 0}, {"sampler", 0}}};
    gltf["materials"] = {{{"name", "four colours"},
                          {"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}, {"metallicFactor", 0.0}, {"roughnessFactor", 0.9}}}}};
    if (masked) {
        gltf["materials"][0]["alphaMode"] = "MASK";
        gltf["materials"][0]["alphaCutoff"] = 0.5;
    }
    gltf["meshes"] = {{{"name", "quad"}, {"primitives", {{{"attributes", {{"POSITION", 0}, {"NORMAL", 1}, {"TEXCOORD_0", 2}}}, {"indices", 3}, {"material", 0}}}}}};
    gltf["nodes"] = {{{"mesh", 0}, {"name", "quad"}}};
    gltf["scenes"] = {{{"nodes", {0}}}};
    gltf["scene"] = 0;
    const auto path = folder / "quad.gltf";
    (void)assets::write_text_file(path, gltf.dump(1));
    return path;
}

// `folder`/two_nodes.glb: the quad's geometry as two primitives of one mesh (orange and violet
// materials); a parent node moved 2 m along +x and turned 90 degrees about +z shows it, and its child,
// scaled by 0.5 and moved 1 m along its parent's +x (so 2 m along +y in the file's frame), shows it
// again.
inline std::filesystem::path write_two_node_glb(const std::filesystem::path& folder) {
    std::filesystem::create_directories(folder);
    nlohmann::json gltf;
    gltf["asset"] = {{"version", "2.0"}};
    std::string buffer = quad_buffer(gltf);
    // The second primitive: the quad's second triangle on its own (indices 0, 3, 2 from byte 134).
    gltf["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", 128}, {"byteLength", 12}});
    gltf["accessors"][3]["count"] = 3;
    gltf["accessors"].push_back({{"bufferView", 4}, {"componentType", 5123}, {"count", 3}, {"type", "SCALAR"}, {"byteOffset", 6}});
    while (buffer.size() % 4) buffer.push_back('\0');
    gltf["buffers"] = {{{"byteLength", buffer.size()}}};
    gltf["materials"] = {{{"name", "orange"}, {"pbrMetallicRoughness", {{"baseColorFactor", {1.0, 0.5, 0.0, 1.0}}}}},
                         {{"name", "violet"}, {"pbrMetallicRoughness", {{"baseColorFactor", {0.5, 0.0, 1.0, 1.0}}, {"metallicFactor", 0.0}}}}};
    gltf["meshes"] = {{{"name", "halves"},
                       {"primitives", {{{"attributes", {{"POSITION", 0}, {"NORMAL", 1}}}, {"indices", 3}, {"material", 0}},
                                       {{"attributes", {{"POSITION", 0}, {"NORMAL", 1}}}, {"indices", 4}, {"material", 1}}}}}};
    const double half = std::sqrt(0.5);
    gltf["nodes"] = {{{"name", "parent"}, {"mesh", 0}, {"translation", {2.0, 0.0, 0.0}}, {"rotation", {0.0, 0.0, half, half}}, {"children", {1}}},
                     {{"name", "child"}, {"mesh", 0}, {"translation", {1.0, 0.0, 0.0}}, {"scale", {0.5, 0.5, 0.5}}}};
    gltf["scenes"] = {{{"nodes", {0}}}};
    gltf["scene"] = 0;
    std::string json = gltf.dump();
    while (json.size() % 4) json.push_back(' ');
    auto u32 = [](std::uint32_t v) { return std::string(reinterpret_cast<const char*>(&v), 4); };
    const std::string glb = "glTF" + u32(2) + u32(static_cast<std::uint32_t>(12 + 8 + json.size() + 8 + buffer.size())) +
                            u32(static_cast<std::uint32_t>(json.size())) + "JSON" + json + u32(static_cast<std::uint32_t>(buffer.size())) + "BIN" +
                            std::string(1, '\0') + buffer;
    const auto path = folder / "two_nodes.glb";
    (void)assets::write_file_atomically(path, glb);
    return path;
}

} // namespace ikebana::test
