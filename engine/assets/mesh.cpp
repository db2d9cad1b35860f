#include "engine/assets/mesh.hpp"

#include <cctype>
#include <cmath>
#include <algorithm>
#include <cstring>
#include <optional>
#include <string_view>
#include <fstream>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
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

auto fail_at(const std::string& label, const std::string& why) { return make_error(ErrorCode::parse_error, label + ": " + why); }

// A node's own transform: its matrix, or translation * rotation * scale.
Result<glm::mat4> local_transform(const tinygltf::Node& node, const std::string& where) {
    glm::dmat4 m(1.0);
    if (node.matrix.size() == 16) {
        for (int c = 0; c < 4; ++c) {
            for (int r = 0; r < 4; ++r) m[c][r] = node.matrix[static_cast<std::size_t>(c * 4 + r)];
        }
    } else {
        glm::dvec3 t(0.0), sc(1.0);
        glm::dquat q(1.0, 0.0, 0.0, 0.0);
        if (node.translation.size() == 3) t = {node.translation[0], node.translation[1], node.translation[2]};
        if (node.rotation.size() == 4) q = glm::dquat(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]);
        if (node.scale.size() == 3) sc = {node.scale[0], node.scale[1], node.scale[2]};
        const double q_length = glm::length(q);
        if (!(q_length > 1e-9)) return make_error(ErrorCode::parse_error, where + "/rotation: not a rotation (a zero quaternion)");
        m = glm::translate(glm::dmat4(1.0), t) * glm::mat4_cast(q / q_length) * glm::scale(glm::dmat4(1.0), sc);
    }
    for (int c = 0; c < 4; ++c) {
        for (int r = 0; r < 4; ++r) {
            if (!std::isfinite(m[c][r]) || std::abs(m[c][r]) > 1e6) return make_error(ErrorCode::parse_error, where + ": a transform that is not finite");
        }
    }
    return glm::mat4(m);
}

// The default scene's root nodes; without scenes, every node that is nobody's child.
Result<std::vector<int>> root_nodes(const tinygltf::Model& model, const std::string& label) {
    std::vector<int> parent(model.nodes.size(), -1);
    for (std::size_t n = 0; n < model.nodes.size(); ++n) {
        for (const int child : model.nodes[n].children) {
            if (child < 0 || static_cast<std::size_t>(child) >= model.nodes.size()) {
                return make_error(ErrorCode::parse_error, label + ": /nodes/" + std::to_string(n) + "/children: node " + std::to_string(child) + " does not exist");
            }
            if (parent[static_cast<std::size_t>(child)] >= 0 || static_cast<std::size_t>(child) == n) {
                return make_error(ErrorCode::parse_error, label + ": /nodes/" + std::to_string(child) + ": a node with two parents (nodes form trees)");
            }
            parent[static_cast<std::size_t>(child)] = static_cast<int>(n);
        }
    }
    // A loop of children has no root above it: walking up from any of its nodes comes back to it.
    for (std::size_t n = 0; n < model.nodes.size(); ++n) {
        int up = parent[n];
        for (std::size_t steps = 0; up >= 0; ++steps, up = parent[static_cast<std::size_t>(up)]) {
            if (static_cast<std::size_t>(up) == n || steps > model.nodes.size()) {
                return make_error(ErrorCode::parse_error, label + ": /nodes/" + std::to_string(n) + ": the node is its own ancestor");
            }
        }
    }
    std::vector<int> roots;
    if (!model.scenes.empty()) {
        const int chosen = model.defaultScene >= 0 ? model.defaultScene : 0;
        if (static_cast<std::size_t>(chosen) >= model.scenes.size()) return make_error(ErrorCode::parse_error, label + ": /scene: scene " + std::to_string(chosen) + " does not exist");
        for (const int n : model.scenes[static_cast<std::size_t>(chosen)].nodes) {
            if (n < 0 || static_cast<std::size_t>(n) >= model.nodes.size()) {
                return make_error(ErrorCode::parse_error, label + ": /scenes/" + std::to_string(chosen) + "/nodes: node " + std::to_string(n) + " does not exist");
            }
            if (parent[static_cast<std::size_t>(n)] >= 0) return make_error(ErrorCode::parse_error, label + ": /scenes/" + std::to_string(chosen) + "/nodes: node " + std::to_string(n) + " is another node's child");
            roots.push_back(n);
        }
    } else {
        for (std::size_t n = 0; n < model.nodes.size(); ++n) {
            if (parent[n] < 0) roots.push_back(static_cast<int>(n));
        }
    }
    return roots;
}

// A material as the shading uses it; its pictures by image index (a texture names its image).
Result<MeshMaterial> read_material(const tinygltf::Model& model, std::size_t index, const std::string& label) {
    const auto& m = model.materials[index];
    const std::string where = label + ": /materials/" + std::to_string(index);
    MeshMaterial out;
    out.name = m.name;
    const auto& pbr = m.pbrMetallicRoughness;
    if (pbr.baseColorFactor.size() == 4) out.base_colour = {pbr.baseColorFactor[0], pbr.baseColorFactor[1], pbr.baseColorFactor[2], pbr.baseColorFactor[3]};
    out.metallic = static_cast<float>(pbr.metallicFactor);
    out.roughness = static_cast<float>(pbr.roughnessFactor);
    out.normal_scale = static_cast<float>(m.normalTexture.scale);
    for (const float v : {out.base_colour.r, out.base_colour.g, out.base_colour.b, out.base_colour.a, out.metallic, out.roughness}) {
        if (!std::isfinite(v) || v < 0.0f || v > 1.0f) return make_error(ErrorCode::parse_error, where + "/pbrMetallicRoughness: factors must be within 0..1");
    }
    if (!std::isfinite(out.normal_scale) || std::abs(out.normal_scale) > 100.0f) return make_error(ErrorCode::parse_error, where + "/normalTexture/scale: not a sensible number");
    auto image_of = [&](int texture, const char* field, TextureSampling& sampling) -> Result<int> {
        if (texture < 0) return -1;
        if (static_cast<std::size_t>(texture) >= model.textures.size()) {
            return make_error(ErrorCode::parse_error, where + "/" + field + ": texture " + std::to_string(texture) + " does not exist");
        }
        const int sampler = model.textures[static_cast<std::size_t>(texture)].sampler;
        if (sampler >= 0 && static_cast<std::size_t>(sampler) < model.samplers.size()) {
            const auto& s = model.samplers[static_cast<std::size_t>(sampler)];
            const auto wrap = [](int mode) {
                return mode == TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE     ? TextureSampling::Wrap::clamp
                       : mode == TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT ? TextureSampling::Wrap::mirror
                                                                       : TextureSampling::Wrap::repeat;
            };
            sampling.nearest_magnification = s.magFilter == TINYGLTF_TEXTURE_FILTER_NEAREST;
            sampling.nearest_minification = s.minFilter == TINYGLTF_TEXTURE_FILTER_NEAREST || s.minFilter == TINYGLTF_TEXTURE_FILTER_NEAREST_MIPMAP_NEAREST ||
                                            s.minFilter == TINYGLTF_TEXTURE_FILTER_NEAREST_MIPMAP_LINEAR;
            sampling.wrap_u = wrap(s.wrapS);
            sampling.wrap_v = wrap(s.wrapT);
        }
        const int source = model.textures[static_cast<std::size_t>(texture)].source;
        if (source < 0 || static_cast<std::size_t>(source) >= model.images.size()) {
            return make_error(ErrorCode::parse_error, label + ": /textures/" + std::to_string(texture) + "/source: image " + std::to_string(source) + " does not exist");
        }
        const auto& image = model.images[static_cast<std::size_t>(source)];
        if (image.image.empty() || image.width <= 0 || image.height <= 0 || image.component != 4 || image.bits != 8) {
            const std::string named = image.uri.empty() || image.uri.rfind("data:", 0) == 0 ? "the picture" : "\"" + image.uri + "\"";
            return make_error(ErrorCode::parse_error, label + ": /images/" + std::to_string(source) + ": " + named +
                                                          " could not be read (not in the mesh's folder, or not a PNG or JPEG)");
        }
        return source;
    };
    auto base = image_of(pbr.baseColorTexture.index, "pbrMetallicRoughness/baseColorTexture", out.base_colour_sampling);
    if (!base) return std::move(base).error();
    auto normal = image_of(m.normalTexture.index, "normalTexture", out.normal_sampling);
    if (!normal) return std::move(normal).error();
    out.base_colour_image = *base;
    out.normal_image = *normal;
    if (m.alphaMode == "MASK") {
        out.alpha_cutoff = static_cast<float>(m.alphaCutoff);
        if (!std::isfinite(out.alpha_cutoff) || out.alpha_cutoff < 0.0f || out.alpha_cutoff > 1.0f) return make_error(ErrorCode::parse_error, where + "/alphaCutoff: must be within 0..1");
    } else if (m.alphaMode == "BLEND") {
        out.alpha_cutoff = 0.5f;
    }
    return out;
}

// Per-vertex tangents from the texture coordinates (for normal maps without a TANGENT attribute): the
// direction of increasing u on each triangle, summed at its corners, made perpendicular to the normal.
void compute_tangents(MeshData& mesh, std::size_t first_vertex) {
    const std::size_t n = mesh.positions.size();
    std::vector<glm::vec3> tan(n - first_vertex, glm::vec3(0.0f)), bitan(n - first_vertex, glm::vec3(0.0f));
    for (std::size_t i = 0; i + 2 < mesh.indices.size(); i += 3) {
        const std::uint32_t a = mesh.indices[i], b = mesh.indices[i + 1], c = mesh.indices[i + 2];
        if (a < first_vertex || b < first_vertex || c < first_vertex) continue;
        const glm::vec3 e1 = mesh.positions[b] - mesh.positions[a], e2 = mesh.positions[c] - mesh.positions[a];
        const glm::vec2 d1 = mesh.uvs[b] - mesh.uvs[a], d2 = mesh.uvs[c] - mesh.uvs[a];
        const float det = d1.x * d2.y - d2.x * d1.y;
        if (std::abs(det) < 1e-12f) continue;
        const glm::vec3 t = (e1 * d2.y - e2 * d1.y) / det;
        const glm::vec3 bt = (e2 * d1.x - e1 * d2.x) / det;
        for (const std::uint32_t v : {a, b, c}) {
            tan[v - first_vertex] += t;
            bitan[v - first_vertex] += bt;
        }
    }
    for (std::size_t v = first_vertex; v < n; ++v) {
        const glm::vec3 nrm = mesh.normals[v];
        glm::vec3 t = tan[v - first_vertex] - nrm * glm::dot(nrm, tan[v - first_vertex]);
        if (glm::length(t) < 1e-9f) t = std::abs(nrm.x) < 0.9f ? glm::cross(nrm, glm::vec3(1, 0, 0)) : glm::cross(nrm, glm::vec3(0, 1, 0));
        t = glm::normalize(t);
        const float sign = glm::dot(glm::cross(nrm, t), bitan[v - first_vertex]) < 0.0f ? -1.0f : 1.0f;
        mesh.tangents[v] = glm::vec4(t, sign);
    }
}

// One triangle primitive, moved by `world`, appended to `mesh` as a part.
Result<void> append_primitive(const tinygltf::Model& model, const tinygltf::Primitive& prim, const glm::mat4& world, const std::string& where,
                              const std::string& label, MeshData& mesh) {
    const auto pos_it = prim.attributes.find("POSITION");
    const auto nrm_it = prim.attributes.find("NORMAL");
    if (pos_it == prim.attributes.end()) return fail_at(label, where + ": no POSITION attribute");
    if (nrm_it == prim.attributes.end()) return fail_at(label, where + ": no NORMAL attribute (normals are required)");
    auto pos = accessor_bytes(model, pos_it->second, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, label, "POSITION");
    if (!pos) return std::move(pos).error();
    auto nrm = accessor_bytes(model, nrm_it->second, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, label, "NORMAL");
    if (!nrm) return std::move(nrm).error();
    if (pos->count != nrm->count) return fail_at(label, where + ": POSITION and NORMAL counts differ");
    std::optional<Range> uv, tangent;
    if (const auto it = prim.attributes.find("TEXCOORD_0"); it != prim.attributes.end()) {
        auto r = accessor_bytes(model, it->second, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC2, label, "TEXCOORD_0 (float pairs)");
        if (!r) return std::move(r).error();
        if (r->count != pos->count) return fail_at(label, where + ": TEXCOORD_0 and POSITION counts differ");
        uv = *r;
    }
    if (const auto it = prim.attributes.find("TANGENT"); it != prim.attributes.end()) {
        auto r = accessor_bytes(model, it->second, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC4, label, "TANGENT");
        if (!r) return std::move(r).error();
        if (r->count != pos->count) return fail_at(label, where + ": TANGENT and POSITION counts differ");
        tangent = *r;
    }
    if (pos->count > max_mesh_vertices - mesh.positions.size()) {
        return fail_at(label, "more than the " + std::to_string(max_mesh_vertices) + " vertices a flower's part may have");
    }
    const std::size_t first_vertex = mesh.positions.size();
    const glm::mat3 linear(world);
    const glm::mat3 normal_matrix = glm::transpose(glm::inverse(linear));
    if (!(std::abs(glm::determinant(linear)) > 1e-12f)) return fail_at(label, where + ": its node's transform flattens it (scale 0)");
    mesh.positions.resize(first_vertex + pos->count);
    mesh.normals.resize(first_vertex + pos->count);
    mesh.uvs.resize(first_vertex + pos->count, glm::vec2(0.0f));
    mesh.tangents.resize(first_vertex + pos->count, glm::vec4(0.0f));
    for (std::size_t i = 0; i < pos->count; ++i) {
        glm::vec3 p, n;
        std::memcpy(&p, pos->data + i * pos->stride, sizeof(glm::vec3));
        std::memcpy(&n, nrm->data + i * nrm->stride, sizeof(glm::vec3));
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z) || !std::isfinite(n.x) || !std::isfinite(n.y) || !std::isfinite(n.z) ||
            glm::length(n) < 1e-6f) {
            return fail_at(label, "vertex " + std::to_string(i) + " is not finite or has a zero normal");
        }
        const std::size_t v = first_vertex + i;
        mesh.positions[v] = glm::vec3(world * glm::vec4(p, 1.0f));
        mesh.normals[v] = glm::normalize(normal_matrix * n);
        if (uv) {
            std::memcpy(&mesh.uvs[v], uv->data + i * uv->stride, sizeof(glm::vec2));
            if (!std::isfinite(mesh.uvs[v].x) || !std::isfinite(mesh.uvs[v].y)) return fail_at(label, where + ": a texture coordinate is not finite");
        }
        if (tangent) {
            glm::vec4 t;
            std::memcpy(&t, tangent->data + i * tangent->stride, sizeof(glm::vec4));
            const glm::vec3 moved = linear * glm::vec3(t);
            if (!std::isfinite(t.w) || !(glm::length(moved) > 1e-9f)) return fail_at(label, where + ": a tangent is not finite or zero");
            mesh.tangents[v] = glm::vec4(glm::normalize(moved), t.w < 0.0f ? -1.0f : 1.0f);
        }
    }
    MeshPart part;
    part.first_index = static_cast<std::uint32_t>(mesh.indices.size());
    if (prim.indices >= 0) {
        const auto acc_type = static_cast<std::size_t>(prim.indices) < model.accessors.size() ? model.accessors[static_cast<std::size_t>(prim.indices)].componentType : -1;
        if (acc_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT && acc_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
            acc_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE) {
            return fail_at(label, "indices must be unsigned 8-, 16- or 32-bit");
        }
        auto idx = accessor_bytes(model, prim.indices, acc_type, TINYGLTF_TYPE_SCALAR, label, "indices");
        if (!idx) return std::move(idx).error();
        if (idx->count > 6 * max_mesh_vertices - mesh.indices.size()) {
            return fail_at(label, std::to_string(idx->count) + " indices, more than a mesh of " + std::to_string(max_mesh_vertices) + " vertices needs");
        }
        if (idx->count % 3 != 0) return fail_at(label, "index count is not a whole number of triangles");
        for (std::size_t i = 0; i < idx->count; ++i) {
            std::uint32_t value = 0;
            if (acc_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT) {
                std::memcpy(&value, idx->data + i * idx->stride, 4);
            } else if (acc_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT) {
                std::uint16_t v16;
                std::memcpy(&v16, idx->data + i * idx->stride, 2);
                value = v16;
            } else {
                value = idx->data[i * idx->stride];
            }
            if (value >= pos->count) return fail_at(label, "index " + std::to_string(i) + " points past the vertices");
            mesh.indices.push_back(static_cast<std::uint32_t>(first_vertex) + value);
        }
    } else {
        if (pos->count % 3 != 0) return fail_at(label, "index count is not a whole number of triangles");
        for (std::size_t i = 0; i < pos->count; ++i) mesh.indices.push_back(static_cast<std::uint32_t>(first_vertex + i));
    }
    part.index_count = static_cast<std::uint32_t>(mesh.indices.size()) - part.first_index;
    if (prim.material >= 0) {
        if (static_cast<std::size_t>(prim.material) >= model.materials.size()) return fail_at(label, where + "/material: material " + std::to_string(prim.material) + " does not exist");
        part.material = prim.material;
    }
    const bool normal_mapped = part.material >= 0 && model.materials[static_cast<std::size_t>(part.material)].normalTexture.index >= 0;
    if (normal_mapped && !tangent) compute_tangents(mesh, first_vertex);
    if (part.index_count > 0) mesh.parts.push_back(part);
    return Ok{};
}

Result<MeshData> from_model(const tinygltf::Model& model, const std::string& label) {
    auto roots = root_nodes(model, label);
    if (!roots) return std::move(roots).error();
    MeshData mesh;
    // Depth first, each node once (the nodes are trees: checked above).
    std::vector<std::pair<int, glm::mat4>> stack;
    for (auto it = roots->rbegin(); it != roots->rend(); ++it) stack.emplace_back(*it, glm::mat4(1.0f));
    while (!stack.empty()) {
        const auto [n, parent] = stack.back();
        stack.pop_back();
        const auto& node = model.nodes[static_cast<std::size_t>(n)];
        const std::string where = "/nodes/" + std::to_string(n);
        auto local = local_transform(node, label + ": " + where);
        if (!local) return std::move(local).error();
        const glm::mat4 world = parent * *local;
        if (node.mesh >= 0) {
            if (static_cast<std::size_t>(node.mesh) >= model.meshes.size()) return fail_at(label, where + "/mesh: mesh " + std::to_string(node.mesh) + " does not exist");
            const auto& gm = model.meshes[static_cast<std::size_t>(node.mesh)];
            if (mesh.name.empty()) mesh.name = gm.name;
            for (std::size_t p = 0; p < gm.primitives.size(); ++p) {
                if (gm.primitives[p].mode != TINYGLTF_MODE_TRIANGLES) continue; // points and lines (loose edges) are not drawn
                auto ok = append_primitive(model, gm.primitives[p], world, "/meshes/" + std::to_string(node.mesh) + "/primitives/" + std::to_string(p), label, mesh);
                if (!ok) return std::move(ok).error();
            }
        }
        for (auto it = node.children.rbegin(); it != node.children.rend(); ++it) stack.emplace_back(*it, world);
    }
    // A file of meshes and no nodes (some exporters, and hand-made files): its first mesh as it is.
    if (model.nodes.empty() && !model.meshes.empty()) {
        mesh.name = model.meshes[0].name;
        for (std::size_t p = 0; p < model.meshes[0].primitives.size(); ++p) {
            if (model.meshes[0].primitives[p].mode != TINYGLTF_MODE_TRIANGLES) continue;
            auto ok = append_primitive(model, model.meshes[0].primitives[p], glm::mat4(1.0f), "/meshes/0/primitives/" + std::to_string(p), label, mesh);
            if (!ok) return std::move(ok).error();
        }
    }
    if (mesh.parts.empty()) {
        if (model.meshes.empty()) return fail_at(label, "no mesh primitive");
        return fail_at(label, "no triangles (a mesh primitive is not triangles, or no node shows a mesh)");
    }
    // Materials and pictures: the ones the parts use, renumbered.
    std::vector<int> material_of(model.materials.size(), -1), image_of(model.images.size(), -1);
    for (auto& part : mesh.parts) {
        if (part.material < 0) continue;
        auto& mine = material_of[static_cast<std::size_t>(part.material)];
        if (mine < 0) {
            auto material = read_material(model, static_cast<std::size_t>(part.material), label);
            if (!material) return std::move(material).error();
            for (int* image : {&material->base_colour_image, &material->normal_image}) {
                if (*image < 0) continue;
                auto& kept = image_of[static_cast<std::size_t>(*image)];
                if (kept < 0) {
                    const auto& source = model.images[static_cast<std::size_t>(*image)];
                    kept = static_cast<int>(mesh.images.size());
                    mesh.images.push_back(DecodedImage{static_cast<std::uint32_t>(source.width), static_cast<std::uint32_t>(source.height), source.image});
                }
                *image = kept;
            }
            mine = static_cast<int>(mesh.materials.size());
            mesh.materials.push_back(std::move(*material));
        }
        part.material = mine;
    }
    // Without texture coordinates or normal maps, the vertices carry none.
    if (std::none_of(mesh.materials.begin(), mesh.materials.end(), [](const MeshMaterial& m) { return m.normal_image >= 0; }) &&
        std::none_of(mesh.tangents.begin(), mesh.tangents.end(), [](const glm::vec4& t) { return t != glm::vec4(0.0f); })) {
        mesh.tangents.clear();
    }
    if (std::all_of(mesh.uvs.begin(), mesh.uvs.end(), [](const glm::vec2& t) { return t == glm::vec2(0.0f); })) mesh.uvs.clear();
    return mesh;
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

// Pictures are decoded with stb (engine/assets/image): each at most 4096 a side by its header, and all
// of one mesh at most 256 MiB of pixels, so a small file naming many huge pictures costs nothing.
struct PictureBudget {
    std::string label;
    std::size_t bytes_left = 256ull << 20;
};

bool decode_picture(tinygltf::Image* image, const int index, std::string* err, std::string*, int, int, const unsigned char* bytes, int size, void* user) {
    auto& budget = *static_cast<PictureBudget*>(user);
    auto decoded = decode_image(std::string_view(reinterpret_cast<const char*>(bytes), static_cast<std::size_t>(std::max(size, 0))),
                                budget.label + ": /images/" + std::to_string(index));
    if (decoded && decoded->pixels.size() > budget.bytes_left) {
        decoded = make_error(ErrorCode::parse_error, budget.label + ": /images/" + std::to_string(index) + ": the mesh's pictures come to more than 256 MiB");
    }
    if (!decoded) {
        if (err) *err += decoded.error().message;
        return false;
    }
    budget.bytes_left -= decoded->pixels.size();
    image->width = static_cast<int>(decoded->width);
    image->height = static_cast<int>(decoded->height);
    image->component = 4;
    image->bits = 8;
    image->pixel_type = TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE;
    image->image = std::move(decoded->pixels);
    return true;
}

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
    {
        const auto json = json_part(bytes, binary);
        const auto root = nlohmann::json::parse(json.begin(), json.end(), nullptr, false);
        if (!root.is_discarded() && root.is_object()) {
            if (auto uris = check_uris(root, label); !uris) return std::move(uris).error();
        }
    }
    if (bytes.size() > max_text_file_bytes) return make_error(ErrorCode::parse_error, label + ": larger than 64 MiB");
    tinygltf::TinyGLTF loader;
    MeshFolder files{folder};
    loader.SetFsCallbacks(tinygltf::FsCallbacks{folder_file_exists, no_expansion, read_folder_file, never_write, &files});
    PictureBudget budget{label};
    loader.SetImageLoader(decode_picture, &budget);
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
        while (!err.empty() && std::isspace(static_cast<unsigned char>(err.back()))) err.pop_back();
        std::replace(err.begin(), err.end(), '\n', ';'); // one line: tinygltf ends each of its messages with a line break
        if (err.size() > 300) err = err.substr(0, 300) + "...";
        return make_error(ErrorCode::parse_error, label + ": not a readable glTF 2.0 file: " + err);
    }
    return from_model(model, label);
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

std::string base64(std::string_view bytes) {
    static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (std::size_t i = 0; i < bytes.size(); i += 3) {
        const std::uint32_t b0 = static_cast<unsigned char>(bytes[i]);
        const std::uint32_t b1 = i + 1 < bytes.size() ? static_cast<unsigned char>(bytes[i + 1]) : 0u;
        const std::uint32_t b2 = i + 2 < bytes.size() ? static_cast<unsigned char>(bytes[i + 2]) : 0u;
        const std::uint32_t triple = (b0 << 16) | (b1 << 8) | b2;
        out += table[(triple >> 18) & 63];
        out += table[(triple >> 12) & 63];
        out += i + 1 < bytes.size() ? table[(triple >> 6) & 63] : '=';
        out += i + 2 < bytes.size() ? table[triple & 63] : '=';
    }
    return out;
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
    j["buffers"] = {{{"byteLength", bytes.size()}, {"uri", "data:application/octet-stream;base64," + base64(std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()))}}};
    return assets::json_text(j, 1) + "\n";
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
