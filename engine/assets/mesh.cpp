#include "engine/assets/mesh.hpp"

#include <cmath>
#include <cstring>
#include <fstream>

#include <nlohmann/json.hpp>
#include <tiny_gltf.h>

#include "engine/assets/json_checker.hpp"

namespace ikebana::assets {

namespace {

struct Range {
    const unsigned char* data = nullptr;
    std::size_t stride = 0;
    std::size_t count = 0;
};

// Resolves an accessor to raw bytes after checking every index and bound.
Result<Range> accessor_bytes(const tinygltf::Model& model, int accessor_index, int component_type, int type,
                             const std::string& label, const std::string& what) {
    auto fail = [&](const std::string& why) { return make_error(ErrorCode::parse_error, label + ": " + what + ": " + why); };
    if (accessor_index < 0 || static_cast<std::size_t>(accessor_index) >= model.accessors.size()) {
        return fail("accessor " + std::to_string(accessor_index) + " does not exist");
    }
    const auto& acc = model.accessors[static_cast<std::size_t>(accessor_index)];
    if (acc.componentType != component_type || acc.type != type) {
        return fail("accessor " + std::to_string(accessor_index) + " has the wrong component type");
    }
    if (acc.sparse.isSparse) return fail("sparse accessors are not supported");
    if (acc.bufferView < 0 || static_cast<std::size_t>(acc.bufferView) >= model.bufferViews.size()) {
        return fail("buffer view " + std::to_string(acc.bufferView) + " does not exist");
    }
    const auto& view = model.bufferViews[static_cast<std::size_t>(acc.bufferView)];
    if (view.buffer < 0 || static_cast<std::size_t>(view.buffer) >= model.buffers.size()) {
        return fail("buffer " + std::to_string(view.buffer) + " does not exist");
    }
    const auto& buffer = model.buffers[static_cast<std::size_t>(view.buffer)];
    const std::size_t element = static_cast<std::size_t>(tinygltf::GetComponentSizeInBytes(static_cast<std::uint32_t>(acc.componentType))) *
                                static_cast<std::size_t>(tinygltf::GetNumComponentsInType(static_cast<std::uint32_t>(acc.type)));
    const std::size_t stride = view.byteStride ? view.byteStride : element;
    if (stride < element) return fail("byte stride smaller than an element");
    if (view.byteOffset > buffer.data.size() || view.byteLength > buffer.data.size() - view.byteOffset) {
        return fail("buffer view runs past the end of its buffer");
    }
    if (acc.count == 0) return fail("accessor is empty");
    if (acc.byteOffset > view.byteLength || (acc.count - 1) > (view.byteLength - acc.byteOffset) / stride ||
        acc.byteOffset + (acc.count - 1) * stride + element > view.byteLength) {
        return fail("accessor runs past the end of its buffer view");
    }
    return Range{buffer.data.data() + view.byteOffset + acc.byteOffset, stride, acc.count};
}

Result<MeshData> from_model(const tinygltf::Model& model, const std::string& label) {
    if (model.meshes.empty() || model.meshes[0].primitives.empty()) {
        return make_error(ErrorCode::parse_error, label + ": no mesh primitive");
    }
    const auto& prim = model.meshes[0].primitives[0];
    if (prim.mode != TINYGLTF_MODE_TRIANGLES) return make_error(ErrorCode::parse_error, label + ": primitive is not triangles");
    const auto pos_it = prim.attributes.find("POSITION");
    const auto nrm_it = prim.attributes.find("NORMAL");
    if (pos_it == prim.attributes.end()) return make_error(ErrorCode::parse_error, label + ": no POSITION attribute");
    if (nrm_it == prim.attributes.end()) return make_error(ErrorCode::parse_error, label + ": no NORMAL attribute (normals are required)");
    auto pos = accessor_bytes(model, pos_it->second, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, label, "POSITION");
    if (!pos) return std::move(pos).error();
    auto nrm = accessor_bytes(model, nrm_it->second, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, label, "NORMAL");
    if (!nrm) return std::move(nrm).error();
    if (pos->count != nrm->count) return make_error(ErrorCode::parse_error, label + ": POSITION and NORMAL counts differ");

    MeshData mesh;
    mesh.name = model.meshes[0].name;
    mesh.positions.resize(pos->count);
    mesh.normals.resize(pos->count);
    for (std::size_t i = 0; i < pos->count; ++i) {
        std::memcpy(&mesh.positions[i], pos->data + i * pos->stride, sizeof(glm::vec3));
        std::memcpy(&mesh.normals[i], nrm->data + i * nrm->stride, sizeof(glm::vec3));
        const glm::vec3& p = mesh.positions[i];
        glm::vec3& n = mesh.normals[i];
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z) || !std::isfinite(n.x) ||
            !std::isfinite(n.y) || !std::isfinite(n.z) || glm::length(n) < 1e-6f) {
            return make_error(ErrorCode::parse_error, label + ": vertex " + std::to_string(i) + " is not finite or has a zero normal");
        }
        n = glm::normalize(n);
    }
    if (prim.indices >= 0) {
        const auto& acc_type = static_cast<std::size_t>(prim.indices) < model.accessors.size()
                                   ? model.accessors[static_cast<std::size_t>(prim.indices)].componentType
                                   : -1;
        if (acc_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT && acc_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT) {
            return make_error(ErrorCode::parse_error, label + ": indices must be unsigned 16- or 32-bit");
        }
        auto idx = accessor_bytes(model, prim.indices, acc_type, TINYGLTF_TYPE_SCALAR, label, "indices");
        if (!idx) return std::move(idx).error();
        mesh.indices.resize(idx->count);
        for (std::size_t i = 0; i < idx->count; ++i) {
            if (acc_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT) {
                std::memcpy(&mesh.indices[i], idx->data + i * idx->stride, 4);
            } else {
                std::uint16_t v;
                std::memcpy(&v, idx->data + i * idx->stride, 2);
                mesh.indices[i] = v;
            }
            if (mesh.indices[i] >= mesh.positions.size()) {
                return make_error(ErrorCode::parse_error, label + ": index " + std::to_string(i) + " points past the vertices");
            }
        }
    } else {
        for (std::uint32_t i = 0; i < mesh.positions.size(); ++i) mesh.indices.push_back(i);
    }
    if (mesh.indices.empty() || mesh.indices.size() % 3 != 0) {
        return make_error(ErrorCode::parse_error, label + ": index count is not a whole number of triangles");
    }
    return mesh;
}

std::string base64(const std::vector<unsigned char>& bytes) {
    static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (std::size_t i = 0; i < bytes.size(); i += 3) {
        const std::uint32_t b0 = bytes[i];
        const std::uint32_t b1 = i + 1 < bytes.size() ? bytes[i + 1] : 0;
        const std::uint32_t b2 = i + 2 < bytes.size() ? bytes[i + 2] : 0;
        const std::uint32_t triple = (b0 << 16) | (b1 << 8) | b2;
        out += table[(triple >> 18) & 63];
        out += table[(triple >> 12) & 63];
        out += i + 1 < bytes.size() ? table[(triple >> 6) & 63] : '=';
        out += i + 2 < bytes.size() ? table[triple & 63] : '=';
    }
    return out;
}

} // namespace

Result<MeshData> parse_gltf_mesh(const std::string& text, const std::string& label) {
    tinygltf::TinyGLTF loader;
    tinygltf::Model model;
    std::string err;
    std::string warn;
    // Only embedded (data URI) buffers: an empty base dir keeps a file from reading others.
    bool ok = false;
    try {
        ok = loader.LoadASCIIFromString(&model, &err, &warn, text.data(), static_cast<unsigned int>(text.size()), "");
    } catch (const std::exception& e) {
        err = e.what();
    }
    if (!ok) {
        if (err.size() > 300) err = err.substr(0, 300) + "...";
        return make_error(ErrorCode::parse_error, label + ": not a readable glTF 2.0 file: " + err);
    }
    return from_model(model, label);
}

Result<MeshData> load_gltf_mesh(const std::filesystem::path& path) {
    auto text = read_text_file(path);
    if (!text) return std::move(text).error();
    return parse_gltf_mesh(*text, path.string());
}

std::string gltf_text(const MeshData& mesh) {
    std::vector<unsigned char> bytes;
    auto append = [&bytes](const void* data, std::size_t size) {
        const auto* p = static_cast<const unsigned char*>(data);
        bytes.insert(bytes.end(), p, p + size);
    };
    append(mesh.positions.data(), mesh.positions.size() * sizeof(glm::vec3));
    append(mesh.normals.data(), mesh.normals.size() * sizeof(glm::vec3));
    append(mesh.indices.data(), mesh.indices.size() * sizeof(std::uint32_t));
    glm::vec3 lo(1e30f);
    glm::vec3 hi(-1e30f);
    for (const auto& p : mesh.positions) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    const std::size_t vbytes = mesh.positions.size() * sizeof(glm::vec3);
    const std::size_t ibytes = mesh.indices.size() * sizeof(std::uint32_t);
    nlohmann::ordered_json j;
    j["asset"] = {{"version", "2.0"}, {"generator", "ikebana assets meshes"}};
    j["scene"] = 0;
    j["scenes"] = {{{"nodes", {0}}}};
    j["nodes"] = {{{"mesh", 0}, {"name", mesh.name}}};
    j["meshes"] = {{{"name", mesh.name},
                    {"primitives", {{{"attributes", {{"POSITION", 0}, {"NORMAL", 1}}}, {"indices", 2}, {"mode", 4}}}}}};
    j["accessors"] = {
        {{"bufferView", 0}, {"componentType", 5126}, {"count", mesh.positions.size()}, {"type", "VEC3"},
         {"min", {lo.x, lo.y, lo.z}}, {"max", {hi.x, hi.y, hi.z}}},
        {{"bufferView", 1}, {"componentType", 5126}, {"count", mesh.normals.size()}, {"type", "VEC3"}},
        {{"bufferView", 2}, {"componentType", 5125}, {"count", mesh.indices.size()}, {"type", "SCALAR"}}};
    j["bufferViews"] = {{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", vbytes}, {"target", 34962}},
                        {{"buffer", 0}, {"byteOffset", vbytes}, {"byteLength", vbytes}, {"target", 34962}},
                        {{"buffer", 0}, {"byteOffset", 2 * vbytes}, {"byteLength", ibytes}, {"target", 34963}}};
    j["buffers"] = {{{"byteLength", bytes.size()}, {"uri", "data:application/octet-stream;base64," + base64(bytes)}}};
    return j.dump(1) + "\n";
}

Result<void> write_gltf_mesh(const std::filesystem::path& path, const MeshData& mesh) {
    // Written beside the target and renamed, so a failed write never leaves half a file.
    const auto temporary = path.string() + ".tmp";
    {
        std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
        if (!out) return make_error(ErrorCode::io_error, temporary + ": cannot be opened for writing");
        out << gltf_text(mesh);
        if (!out) return make_error(ErrorCode::io_error, temporary + ": write failed");
    }
    std::error_code ec;
    std::filesystem::rename(temporary, path, ec);
    if (ec) return make_error(ErrorCode::io_error, path.string() + ": " + ec.message());
    return {};
}

MeshData placeholder_mesh() {
    MeshData m;
    m.name = "placeholder";
    const glm::vec3 axes[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    const int faces[8][3] = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
    for (const auto& f : faces) {
        const glm::vec3 a = 0.01f * axes[f[0]];
        const glm::vec3 b = 0.01f * axes[f[1]];
        const glm::vec3 c = 0.01f * axes[f[2]];
        const glm::vec3 n = glm::normalize(glm::cross(b - a, c - a));
        for (const auto& p : {a, b, c}) {
            m.indices.push_back(static_cast<std::uint32_t>(m.positions.size()));
            m.positions.push_back(p);
            m.normals.push_back(n);
        }
    }
    return m;
}

} // namespace ikebana::assets
