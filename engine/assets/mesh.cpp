#include "engine/assets/mesh.hpp"

#include <cctype>
#include <cmath>
#include <algorithm>
#include <cstring>
#include <optional>
#include <string_view>
#include <fstream>

#include <nlohmann/json.hpp>
#include <tiny_gltf.h>

#include "engine/assets/files.hpp"
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
    if (pos->count > max_mesh_vertices) {
        return make_error(ErrorCode::parse_error, label + ": " + std::to_string(pos->count) + " vertices, more than the " +
                                                      std::to_string(max_mesh_vertices) + " a flower's part may have");
    }

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
        if (idx->count > 6 * max_mesh_vertices) {
            return make_error(ErrorCode::parse_error, label + ": " + std::to_string(idx->count) + " indices, more than a mesh of " +
                                                          std::to_string(max_mesh_vertices) + " vertices needs");
        }
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

namespace {

// What tinygltf may read besides the file itself: only regular files inside the mesh's own folder,
// each within the size limit. Absolute URIs and ../ escapes are refused, and so is every external
// file of a mesh given as text (no folder).
struct MeshFolder {
    std::filesystem::path folder;
};

std::optional<std::filesystem::path> inside_folder(const std::string& path, const MeshFolder& f) {
    if (f.folder.empty()) return std::nullopt;
    std::error_code ec;
    const auto root = std::filesystem::weakly_canonical(f.folder, ec);
    if (ec) return std::nullopt;
    const auto target = std::filesystem::weakly_canonical(std::filesystem::path(path), ec);
    if (ec) return std::nullopt;
    const auto [r, t] = std::mismatch(root.begin(), root.end(), target.begin(), target.end());
    if (r != root.end()) return std::nullopt; // not below the folder (an absolute path, a ../ escape, a link out)
    return target;
}

bool folder_file_exists(const std::string& path, void* user) {
    std::error_code ec;
    const auto inside = inside_folder(path, *static_cast<MeshFolder*>(user));
    return inside && std::filesystem::is_regular_file(*inside, ec);
}

std::string no_expansion(const std::string& path, void*) { return path; } // no ~ or $VARIABLES

bool read_folder_file(std::vector<unsigned char>* out, std::string* err, const std::string& path, void* user) {
    const auto inside = inside_folder(path, *static_cast<MeshFolder*>(user));
    if (!inside) {
        if (err) *err += "refused to read '" + path + "': a mesh reads only files in its own folder";
        return false;
    }
    auto bytes = read_text_file(*inside);
    if (!bytes) {
        if (err) *err += bytes.error().message;
        return false;
    }
    out->assign(bytes->begin(), bytes->end());
    return true;
}

bool never_write(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
    if (err) *err += "a mesh is never written while it is read";
    return false;
}

// Images are never used (a mesh here is its triangles): skipped, never decoded, so a small file naming
// a huge picture costs nothing.
bool skip_image(tinygltf::Image*, const int, std::string*, std::string*, int, int, const unsigned char*, int, void*) { return true; }

// The JSON part of a .glb (or the whole text of a .gltf), for the nesting check before tinygltf, whose
// JSON reader recurses.
std::string_view json_part(const std::string& bytes, bool binary) {
    if (!binary) return bytes;
    if (bytes.size() < 20) return {};
    std::uint32_t length = 0;
    std::memcpy(&length, bytes.data() + 12, 4);
    return std::string_view(bytes).substr(20, std::min<std::size_t>(length, bytes.size() - 20));
}

// A buffer's or image's uri may name only a file in the mesh's own folder: an absolute path, a scheme
// (file://, C:) or a ".." step is refused by name before tinygltf resolves anything.
Result<void> check_uris(const nlohmann::json& root, const std::string& label) {
    for (const char* list : {"buffers", "images"}) {
        const auto it = root.find(list);
        if (it == root.end() || !it->is_array()) continue;
        for (std::size_t i = 0; i < it->size(); ++i) {
            const auto& entry = (*it)[i];
            if (!entry.is_object() || !entry.contains("uri") || !entry["uri"].is_string()) continue;
            const std::string uri = entry["uri"].get<std::string>();
            if (uri.rfind("data:", 0) == 0) continue;
            const std::filesystem::path path(uri);
            bool escapes = path.is_absolute() || uri.find(':') != std::string::npos || uri.find('\\') != std::string::npos;
            for (const auto& step : path) escapes = escapes || step == "..";
            // Percent-escapes that decode to a dot, a slash or a backslash: tinygltf decodes uris.
            std::string lower = uri;
            for (auto& ch : lower) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
            for (const char* escaped : {"%2e", "%2f", "%5c"}) escapes = escapes || lower.find(escaped) != std::string::npos;
            if (escapes) {
                return make_error(ErrorCode::parse_error, label + ": /" + list + "/" + std::to_string(i) + "/uri: '" + uri +
                                                              "' is refused: a mesh reads only files in its own folder, by relative name");
            }
        }
    }
    return {};
}

Result<MeshData> parse_gltf(const std::string& bytes, const std::string& label, const std::filesystem::path& folder) {
    const bool binary = bytes.size() >= 4 && bytes.compare(0, 4, "glTF") == 0;
    if (const auto deep = json_nesting_beyond(json_part(bytes, binary), max_json_depth)) {
        return make_error(ErrorCode::parse_error, label + (binary ? "" : ":" + std::to_string(deep->line) + ":" + std::to_string(deep->column)) +
                                                      ": arrays and objects nest deeper than " + std::to_string(max_json_depth) + " levels");
    }
    std::size_t images = 0;
    {
        const auto json = json_part(bytes, binary);
        const auto root = nlohmann::json::parse(json.begin(), json.end(), nullptr, false);
        if (!root.is_discarded() && root.is_object()) {
            if (auto uris = check_uris(root, label); !uris) return std::move(uris).error();
            if (const auto it = root.find("images"); it != root.end() && it->is_array()) images = it->size();
        }
    }
    if (bytes.size() > max_text_file_bytes) return make_error(ErrorCode::parse_error, label + ": larger than 64 MiB");
    tinygltf::TinyGLTF loader;
    MeshFolder files{folder};
    loader.SetFsCallbacks(tinygltf::FsCallbacks{folder_file_exists, no_expansion, read_folder_file, never_write, &files});
    loader.SetImageLoader(skip_image, nullptr);
    tinygltf::Model model;
    std::string err;
    std::string warn;
    bool ok = false;
    try {
        const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
        const auto size = static_cast<unsigned int>(bytes.size());
        const std::string base = folder.empty() ? std::string() : folder.string();
        ok = binary ? loader.LoadBinaryFromMemory(&model, &err, &warn, data, size, base)
                    : loader.LoadASCIIFromString(&model, &err, &warn, bytes.data(), size, base);
    } catch (const std::exception& e) {
        err = e.what();
    }
    if (!ok) {
        err = without_echo(err);
        if (err.size() > 300) err = err.substr(0, 300) + "...";
        return make_error(ErrorCode::parse_error, label + ": not a readable glTF 2.0 file: " + err);
    }
    auto mesh = from_model(model, label);
    if (mesh) mesh->skipped_images = images;
    return mesh;
}

} // namespace

Result<MeshData> parse_gltf_mesh(const std::string& text, const std::string& label) { return parse_gltf(text, label, {}); }

Result<MeshData> load_gltf_mesh(const std::filesystem::path& path) {
    auto bytes = read_text_file(path);
    if (!bytes) return std::move(bytes).error();
    std::error_code ec;
    const auto folder = std::filesystem::absolute(path, ec).parent_path();
    return parse_gltf(*bytes, path.string(), folder);
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
    return write_file_atomically(path, gltf_text(mesh));
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
