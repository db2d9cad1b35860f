// The renderer's meshes: the built-in ones, glTF files loaded on first use (a placeholder, with a
// warning, when one is missing or broken), and the heads-up panels' triangles of each frame.
#include <algorithm>
#include <cstring>
#include <utility>

#include "engine/render/builtin_meshes.hpp"
#include "engine/render/mesh_lod.hpp"
#include "engine/render/renderer_internal.hpp"
#include "engine/render/stereo_renderer.hpp"

namespace ikebana::render {

using detail::Vertex;

namespace {

std::uint32_t mip_count(std::uint32_t w, std::uint32_t h) {
    std::uint32_t levels = 1;
    while ((std::max(w, h) >> levels) > 0) ++levels;
    return levels;
}

} // namespace

// A picture to a sampled image with its mip chain (each level blitted from the one above), through a
// staging buffer and a command buffer of its own, waited for: meshes are loaded between frames.
// UNORM, not sRGB: the renderer's colours are the display's values (as the species' `look` colours
// are), so a picture is shown as it was painted.
Result<GpuImage> StereoRenderer::upload_texture(const assets::DecodedImage& picture) {
    const VkExtent2D extent{picture.width, picture.height};
    const std::uint32_t levels = mip_count(picture.width, picture.height);
    auto image = create_image(ctx_, VK_FORMAT_R8G8B8A8_UNORM, extent, 1,
                              VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
                              VK_IMAGE_ASPECT_COLOR_BIT, VK_SAMPLE_COUNT_1_BIT, levels);
    if (!image) return std::move(image).error();
    auto staging = create_buffer(ctx_, picture.pixels.size(), VK_BUFFER_USAGE_TRANSFER_SRC_BIT);
    if (!staging) {
        destroy_image(ctx_, *image);
        return std::move(staging).error();
    }
    std::memcpy(staging->mapped, picture.pixels.data(), picture.pixels.size());
    VkCommandBuffer cmd = VK_NULL_HANDLE;
    VkFence done = VK_NULL_HANDLE;
    auto finish = [&](Result<GpuImage> out) {
        if (done) vkDestroyFence(ctx_.device(), done, nullptr);
        if (cmd) vkFreeCommandBuffers(ctx_.device(), pool_, 1, &cmd);
        destroy_buffer(ctx_, *staging);
        if (!out) destroy_image(ctx_, *image);
        return out;
    };
    VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO, nullptr, pool_, VK_COMMAND_BUFFER_LEVEL_PRIMARY, 1};
    if (VkResult r = vkAllocateCommandBuffers(ctx_.device(), &alloc, &cmd); r != VK_SUCCESS) return finish(vulkan_error("vkAllocateCommandBuffers", r));
    VkFenceCreateInfo fence{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    if (VkResult r = vkCreateFence(ctx_.device(), &fence, nullptr, &done); r != VK_SUCCESS) return finish(vulkan_error("vkCreateFence", r));
    VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO, nullptr, VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT, nullptr};
    vkBeginCommandBuffer(cmd, &begin);
    transition_levels(cmd, image->image, 0, levels, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_PIPELINE_STAGE_2_NONE, 0,
                VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT);
    const VkBufferImageCopy copy{0, 0, 0, {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1}, {0, 0, 0}, {extent.width, extent.height, 1}};
    vkCmdCopyBufferToImage(cmd, staging->buffer, image->image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &copy);
    for (std::uint32_t level = 1; level < levels; ++level) {
        transition_levels(cmd, image->image, level - 1, 1, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                    VK_PIPELINE_STAGE_2_COPY_BIT | VK_PIPELINE_STAGE_2_BLIT_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_BLIT_BIT,
                    VK_ACCESS_2_TRANSFER_READ_BIT);
        const auto size = [&](std::uint32_t l) {
            return VkOffset3D{static_cast<std::int32_t>(std::max(1u, extent.width >> l)), static_cast<std::int32_t>(std::max(1u, extent.height >> l)), 1};
        };
        VkImageBlit blit{};
        blit.srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, level - 1, 0, 1};
        blit.srcOffsets[1] = size(level - 1);
        blit.dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, level, 0, 1};
        blit.dstOffsets[1] = size(level);
        vkCmdBlitImage(cmd, image->image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, image->image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &blit,
                       VK_FILTER_LINEAR);
    }
    if (levels > 1) {
        transition_levels(cmd, image->image, 0, levels - 1, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                    VK_PIPELINE_STAGE_2_BLIT_BIT, VK_ACCESS_2_TRANSFER_READ_BIT, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, VK_ACCESS_2_SHADER_SAMPLED_READ_BIT);
    }
    transition_levels(cmd, image->image, levels - 1, 1, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                VK_PIPELINE_STAGE_2_COPY_BIT | VK_PIPELINE_STAGE_2_BLIT_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT,
                VK_ACCESS_2_SHADER_SAMPLED_READ_BIT);
    if (VkResult r = vkEndCommandBuffer(cmd); r != VK_SUCCESS) return finish(vulkan_error("vkEndCommandBuffer", r));
    VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    submit.commandBufferCount = 1;
    submit.pCommandBuffers = &cmd;
    if (VkResult r = vkQueueSubmit(ctx_.queue(), 1, &submit, done); r != VK_SUCCESS) return finish(vulkan_error("vkQueueSubmit", r));
    if (VkResult r = vkWaitForFences(ctx_.device(), 1, &done, VK_TRUE, UINT64_MAX); r != VK_SUCCESS) return finish(vulkan_error("vkWaitForFences", r));
    return finish(*image);
}

// The default material (white, rough, opaque) for the built-in shapes and glTF parts without one.
Result<void> StereoRenderer::prepare_default_material() {
    VkSamplerCreateInfo s{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
    s.magFilter = s.minFilter = VK_FILTER_LINEAR;
    s.mipmapMode = VK_SAMPLER_MIPMAP_MODE_LINEAR;
    s.addressModeU = s.addressModeV = s.addressModeW = VK_SAMPLER_ADDRESS_MODE_REPEAT;
    s.maxLod = VK_LOD_CLAMP_NONE;
    IKEBANA_VK(vkCreateSampler(ctx_.device(), &s, nullptr, &material_sampler_));
    auto white = upload_texture({1, 1, {255, 255, 255, 255}});
    if (!white) return std::move(white).error();
    white_texture_ = *white;
    auto flat = upload_texture({1, 1, {128, 128, 255, 255}});
    if (!flat) return std::move(flat).error();
    flat_normal_texture_ = *flat;
    const VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 2};
    VkDescriptorPoolCreateInfo pool{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO, nullptr, 0, 1, 1, &size};
    IKEBANA_VK(vkCreateDescriptorPool(ctx_.device(), &pool, nullptr, &default_material_pool_));
    VkDescriptorSetAllocateInfo alloc{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO, nullptr, default_material_pool_, 1, &material_layout_};
    IKEBANA_VK(vkAllocateDescriptorSets(ctx_.device(), &alloc, &default_material_));
    const VkDescriptorImageInfo images[2] = {{material_sampler_, white_texture_.view, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL},
                                             {material_sampler_, flat_normal_texture_.view, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL}};
    VkWriteDescriptorSet write{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    write.dstSet = default_material_;
    write.dstBinding = 0;
    write.descriptorCount = 2;
    write.descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
    write.pImageInfo = images;
    vkUpdateDescriptorSets(ctx_.device(), 1, &write, 0, nullptr);
    return Ok{};
}

// A glTF sampler's filters and edges as a Vulkan sampler, made once per kind.
Result<VkSampler> StereoRenderer::sampler_for(const assets::TextureSampling& sampling) {
    if (auto it = samplers_.find(sampling); it != samplers_.end()) return it->second;
    const auto wrap = [](assets::TextureSampling::Wrap w) {
        return w == assets::TextureSampling::Wrap::clamp    ? VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE
               : w == assets::TextureSampling::Wrap::mirror ? VK_SAMPLER_ADDRESS_MODE_MIRRORED_REPEAT
                                                            : VK_SAMPLER_ADDRESS_MODE_REPEAT;
    };
    VkSamplerCreateInfo s{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
    s.magFilter = sampling.nearest_magnification ? VK_FILTER_NEAREST : VK_FILTER_LINEAR;
    s.minFilter = sampling.nearest_minification ? VK_FILTER_NEAREST : VK_FILTER_LINEAR;
    s.mipmapMode = VK_SAMPLER_MIPMAP_MODE_LINEAR;
    s.addressModeU = wrap(sampling.wrap_u);
    s.addressModeV = wrap(sampling.wrap_v);
    s.addressModeW = VK_SAMPLER_ADDRESS_MODE_REPEAT;
    s.maxLod = VK_LOD_CLAMP_NONE;
    VkSampler made = VK_NULL_HANDLE;
    IKEBANA_VK(vkCreateSampler(ctx_.device(), &s, nullptr, &made));
    return samplers_[sampling] = made;
}

void StereoRenderer::destroy_mesh(Mesh& m) {
    destroy_buffer(ctx_, m.vertices);
    destroy_buffer(ctx_, m.indices);
    for (auto& t : m.textures) destroy_image(ctx_, t);
    m.textures.clear();
    if (m.materials) vkDestroyDescriptorPool(ctx_.device(), m.materials, nullptr);
    m.materials = VK_NULL_HANDLE;
}

// A mesh's vertices and indices into buffers of their own (on failure `m` keeps what was made, for
// its caller to destroy).
Result<void> StereoRenderer::upload_geometry(const assets::MeshData& data, Mesh& m) {
    std::vector<Vertex> vertices(data.positions.size());
    for (std::size_t i = 0; i < vertices.size(); ++i) {
        vertices[i] = {data.positions[i], i < data.normals.size() ? data.normals[i] : glm::vec3(0, 0, 1),
                       i < data.uvs.size() ? data.uvs[i] : glm::vec2(0.0f), i < data.tangents.size() ? data.tangents[i] : glm::vec4(0.0f)};
    }
    auto vb = create_buffer(ctx_, std::max<VkDeviceSize>(1, vertices.size() * sizeof(Vertex)), VK_BUFFER_USAGE_VERTEX_BUFFER_BIT);
    if (!vb) return std::move(vb).error();
    m.vertices = *vb;
    if (!vertices.empty()) std::memcpy(m.vertices.mapped, vertices.data(), vertices.size() * sizeof(Vertex));
    auto ib = create_buffer(ctx_, std::max<VkDeviceSize>(1, data.indices.size() * sizeof(std::uint32_t)), VK_BUFFER_USAGE_INDEX_BUFFER_BIT);
    if (!ib) return std::move(ib).error();
    m.indices = *ib;
    if (!data.indices.empty()) std::memcpy(m.indices.mapped, data.indices.data(), data.indices.size() * sizeof(std::uint32_t));
    m.index_count = static_cast<std::uint32_t>(data.indices.size());
    m.span = mesh_span(data);
    return Ok{};
}

Result<StereoRenderer::Mesh> StereoRenderer::upload(const assets::MeshData& data) {
    Mesh m;
    auto fail = [&](Error e) {
        destroy_mesh(m);
        return e;
    };
    if (auto geometry = upload_geometry(data, m); !geometry) return fail(std::move(geometry).error());

    // Pictures, then a set per material (its base colour and normal pictures, or the defaults').
    for (const auto& picture : data.images) {
        auto t = upload_texture(picture);
        if (!t) return fail(std::move(t).error());
        m.textures.push_back(*t);
    }
    std::vector<VkDescriptorSet> sets;
    if (!data.materials.empty()) {
        const auto n = static_cast<std::uint32_t>(data.materials.size());
        const VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 2 * n};
        VkDescriptorPoolCreateInfo pool{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO, nullptr, 0, n, 1, &size};
        if (VkResult r = vkCreateDescriptorPool(ctx_.device(), &pool, nullptr, &m.materials); r != VK_SUCCESS) return fail(vulkan_error("vkCreateDescriptorPool", r));
        const std::vector<VkDescriptorSetLayout> layouts(n, material_layout_);
        sets.resize(n);
        VkDescriptorSetAllocateInfo alloc{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO, nullptr, m.materials, n, layouts.data()};
        if (VkResult r = vkAllocateDescriptorSets(ctx_.device(), &alloc, sets.data()); r != VK_SUCCESS) return fail(vulkan_error("vkAllocateDescriptorSets", r));
        for (std::uint32_t i = 0; i < n; ++i) {
            const auto& material = data.materials[i];
            auto view = [&](int image, const GpuImage& fallback) {
                return image >= 0 && static_cast<std::size_t>(image) < m.textures.size() ? m.textures[static_cast<std::size_t>(image)].view : fallback.view;
            };
            auto base_sampler = sampler_for(material.base_colour_sampling);
            if (!base_sampler) return fail(std::move(base_sampler).error());
            auto normal_sampler = sampler_for(material.normal_sampling);
            if (!normal_sampler) return fail(std::move(normal_sampler).error());
            const VkDescriptorImageInfo images[2] = {
                {*base_sampler, view(material.base_colour_image, white_texture_), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL},
                {*normal_sampler, view(material.normal_image, flat_normal_texture_), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL}};
            VkWriteDescriptorSet write{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
            write.dstSet = sets[i];
            write.dstBinding = 0;
            write.descriptorCount = 2;
            write.descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
            write.pImageInfo = images;
            vkUpdateDescriptorSets(ctx_.device(), 1, &write, 0, nullptr);
        }
    }
    auto part_of = [&](std::uint32_t first, std::uint32_t count, int material) {
        Part part;
        part.first_index = first;
        part.index_count = count;
        part.material = default_material_;
        if (material >= 0 && static_cast<std::size_t>(material) < data.materials.size()) {
            const auto& mat = data.materials[static_cast<std::size_t>(material)];
            part.material = sets[static_cast<std::size_t>(material)];
            part.constants.base_colour = mat.base_colour;
            part.constants.metallic = mat.metallic;
            part.constants.roughness = mat.roughness;
            part.constants.alpha_cutoff = mat.alpha_cutoff;
            part.constants.normal_scale = mat.normal_scale;
            part.constants.normal_mapped = mat.normal_image >= 0 && !data.tangents.empty() ? 1 : 0;
            part.constants.textured = mat.base_colour_image >= 0 && !data.uvs.empty() ? 1 : 0;
            part.shading = mat.alpha_cutoff >= 0.0f ? Shading::masked : Shading::material;
        }
        return part;
    };
    for (const auto& p : data.parts) {
        if (p.first_index <= m.index_count && p.index_count <= m.index_count - p.first_index) m.parts.push_back(part_of(p.first_index, p.index_count, p.material));
    }
    if (data.parts.empty()) m.parts.push_back(part_of(0, m.index_count, -1));
    return m;
}

// A coarse copy's geometry with its fine mesh's parts (the same parts in the same order, as
// clustered_mesh keeps them): its materials are the fine mesh's, not its own.
Result<StereoRenderer::Mesh> StereoRenderer::upload_coarse(const assets::MeshData& coarse, const Mesh& fine) {
    Mesh m;
    if (auto geometry = upload_geometry(coarse, m); !geometry) {
        destroy_mesh(m);
        return std::move(geometry).error();
    }
    m.closed = fine.closed;
    if (coarse.parts.empty() && fine.parts.size() == 1) {
        m.parts = fine.parts;
        m.parts[0].first_index = 0;
        m.parts[0].index_count = m.index_count;
    } else if (coarse.parts.size() == fine.parts.size()) {
        m.parts = fine.parts;
        for (std::size_t i = 0; i < m.parts.size(); ++i) {
            m.parts[i].first_index = coarse.parts[i].first_index;
            m.parts[i].index_count = coarse.parts[i].index_count;
        }
    } else {
        destroy_mesh(m);
        return make_error(ErrorCode::invalid_argument, "a coarse copy of " + coarse.name + " has other parts than its mesh");
    }
    return m;
}

// The mesh `name` (already in meshes_) gets a coarse copy when merging its vertices leaves at most 60 %
// of its triangles; else, or when the copy cannot be made, it is always drawn as it is.
void StereoRenderer::add_coarse_copy(const std::string& name, const assets::MeshData& data) {
    if (options_.coarse_cells < 1) return;
    const auto coarse = clustered_mesh(data, options_.coarse_cells);
    if (coarse.indices.empty() || coarse.indices.size() * 5 > data.indices.size() * 3) return;
    Mesh& fine = meshes_.at(name);
    auto m = upload_coarse(coarse, fine);
    if (!m) return;
    fine.coarse = &(coarse_meshes_[name] = *m);
}

Result<void> StereoRenderer::prepare_builtin_meshes() {
    if (auto ok = prepare_default_material(); !ok) return ok;
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
    // A stem segment is a cylinder stretched along its axis: merging its vertices on a grid would cut
    // across it, so its coarse copy is the six-sided one.
    meshes_.at("cylinder").coarse = &meshes_.at("cylinder_coarse");
    return Ok{};
}

Result<StereoRenderer::Mesh*> StereoRenderer::mesh(const std::string& name) {
    if (auto it = meshes_.find(name); it != meshes_.end()) return &it->second;
    // A mesh the program makes, or a glTF file: a missing or broken one becomes the placeholder, once,
    // with a warning.
    std::optional<assets::MeshData> made = options_.generated_mesh ? options_.generated_mesh(name) : std::nullopt;
    auto data = made ? Result<assets::MeshData>(std::move(*made)) : assets::load_gltf_mesh(options_.asset_dir / name);
    if (!data) {
        warnings_.push_back("mesh " + name + ": " + data.error().message + "; drawing a placeholder");
        data = assets::placeholder_mesh();
    }
    auto m = upload(*data);
    if (!m) {
        // A picture too large for the device, say: drawn as the placeholder instead of failing the frame.
        warnings_.push_back("mesh " + name + ": " + m.error().message + "; drawing a placeholder");
        m = upload(assets::placeholder_mesh());
        if (!m) return std::move(m).error();
        return &(meshes_[name] = *m);
    }
    meshes_[name] = *m;
    add_coarse_copy(name, *data);
    return &meshes_.at(name);
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
