// The renderer's meshes: the built-in ones, glTF files loaded on first use (a placeholder, with a
// warning, when one is missing or broken), and the heads-up panels' triangles of each frame.
#include <algorithm>
#include <cstring>
#include <utility>

#include "engine/render/builtin_meshes.hpp"
#include "engine/render/renderer_internal.hpp"
#include "engine/render/stereo_renderer.hpp"

namespace ikebana::render {

using detail::Vertex;

Result<StereoRenderer::Mesh> StereoRenderer::upload(const assets::MeshData& data) {
    Mesh m;
    std::vector<Vertex> vertices(data.positions.size());
    for (std::size_t i = 0; i < vertices.size(); ++i) vertices[i] = {data.positions[i], i < data.normals.size() ? data.normals[i] : glm::vec3(0, 0, 1)};
    auto vb = create_buffer(ctx_, std::max<VkDeviceSize>(1, vertices.size() * sizeof(Vertex)), VK_BUFFER_USAGE_VERTEX_BUFFER_BIT);
    if (!vb) return std::move(vb).error();
    m.vertices = *vb;
    if (!vertices.empty()) std::memcpy(m.vertices.mapped, vertices.data(), vertices.size() * sizeof(Vertex));
    auto ib = create_buffer(ctx_, std::max<VkDeviceSize>(1, data.indices.size() * sizeof(std::uint32_t)), VK_BUFFER_USAGE_INDEX_BUFFER_BIT);
    if (!ib) {
        destroy_buffer(ctx_, m.vertices);
        return std::move(ib).error();
    }
    m.indices = *ib;
    if (!data.indices.empty()) std::memcpy(m.indices.mapped, data.indices.data(), data.indices.size() * sizeof(std::uint32_t));
    m.index_count = static_cast<std::uint32_t>(data.indices.size());
    return m;
}

Result<void> StereoRenderer::prepare_builtin_meshes() {
    // A coarse cylinder for the hundreds of thin kenzan pins: vertex work is what lavapipe spends on.
    assets::MeshData coarse = cylinder_mesh(6);
    coarse.name = "cylinder_coarse";
    for (const auto& data : {cube_mesh(), cylinder_mesh(), coarse, plane_mesh(), assets::placeholder_mesh()}) {
        auto m = upload(data);
        if (!m) return std::move(m).error();
        m->closed = data.name == "cube" || data.name == "cylinder" || data.name == "cylinder_coarse";
        meshes_[data.name == "placeholder" || data.name.empty() ? "placeholder" : data.name] = *m;
    }
    if (!meshes_.contains("placeholder")) meshes_["placeholder"] = meshes_.rbegin()->second;
    return Ok{};
}

Result<StereoRenderer::Mesh*> StereoRenderer::mesh(const std::string& name) {
    if (auto it = meshes_.find(name); it != meshes_.end()) return &it->second;
    // A glTF file: a missing or broken one becomes the placeholder, once, with a warning.
    auto data = assets::load_gltf_mesh(options_.asset_dir / name);
    if (!data) {
        warnings_.push_back("mesh " + name + ": " + data.error().message + "; drawing a placeholder");
        data = assets::placeholder_mesh();
    }
    auto m = upload(*data);
    if (!m) return std::move(m).error();
    return &(meshes_[name] = *m);
}

std::vector<std::string> StereoRenderer::take_warnings() { return std::exchange(warnings_, {}); }

Result<void> StereoRenderer::fill_overlay(Frame& frame) {
    frame.overlay_ranges.clear();
    std::vector<OverlayVertex> vertices;
    for (const auto& panel : overlay_) {
        const auto tris = overlay_triangles(panel);
        frame.overlay_ranges.emplace_back(static_cast<std::uint32_t>(vertices.size()), static_cast<std::uint32_t>(tris.size()));
        vertices.insert(vertices.end(), tris.begin(), tris.end());
    }
    const VkDeviceSize needed = std::max<std::size_t>(1, vertices.size()) * sizeof(OverlayVertex);
    if (frame.overlay.size < needed) {
        destroy_buffer(ctx_, frame.overlay);
        auto buffer = create_buffer(ctx_, needed * 2, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT);
        if (!buffer) return std::move(buffer).error();
        frame.overlay = *buffer;
    }
    if (!vertices.empty()) std::memcpy(frame.overlay.mapped, vertices.data(), vertices.size() * sizeof(OverlayVertex));
    return Ok{};
}

} // namespace ikebana::render
