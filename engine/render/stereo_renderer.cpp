// The renderer's set-up, its size-dependent targets, and a frame from start to finish: render()
// offscreen, present() to a window. The passes are in render_passes.cpp, the pipelines in
// render_pipelines.cpp, the meshes in render_meshes.cpp.
#include "engine/render/stereo_renderer.hpp"
#include "engine/render/mesh_lod.hpp"
#include "engine/render/screen_layout.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>

#include "engine/render/renderer_internal.hpp"

namespace ikebana::render {

using detail::depth_format;
using detail::FrameUniforms;

namespace {

double ms_since(std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t).count();
}

// Orthographic light looking along `direction` at the shadow's centre (Vulkan depth 0..1).
glm::mat4 light_matrix(const DrawList& list) {
    const glm::vec3 dir = glm::normalize(list.light_direction);
    const float r = list.shadow_radius;
    const glm::vec3 eye = list.shadow_centre - dir * (2.0f * r);
    const glm::vec3 up = std::abs(dir.z) > 0.9f ? glm::vec3(0, 1, 0) : glm::vec3(0, 0, 1);
    const glm::vec3 s = glm::normalize(glm::cross(dir, up));
    const glm::vec3 u = glm::cross(s, dir);
    glm::mat4 view(1.0f);
    view[0][0] = s.x, view[1][0] = s.y, view[2][0] = s.z;
    view[0][1] = u.x, view[1][1] = u.y, view[2][1] = u.z;
    view[0][2] = -dir.x, view[1][2] = -dir.y, view[2][2] = -dir.z;
    view[3][0] = -glm::dot(s, eye), view[3][1] = -glm::dot(u, eye), view[3][2] = glm::dot(dir, eye);
    const float n = 0.0f, f = 4.0f * r;
    glm::mat4 ortho(1.0f);
    ortho[0][0] = 1.0f / r;
    ortho[1][1] = 1.0f / r;
    ortho[2][2] = -1.0f / (f - n);
    ortho[3][2] = -n / (f - n);
    return ortho * view;
}

} // namespace

std::filesystem::path default_shader_dir() {
    if (const char* dir = std::getenv("IKEBANA_SHADERS"); dir && *dir) return dir;
    return IKEBANA_SHADER_DIR;
}

Result<StereoMode> parse_stereo_mode(std::string_view text) {
    if (text == "sbs") return StereoMode::side_by_side;
    if (text == "rows") return StereoMode::rows;
    if (text == "anaglyph") return StereoMode::anaglyph;
    if (text == "mono") return StereoMode::mono;
    return make_error(ErrorCode::invalid_argument, "stereo mode '" + std::string(text) + "': expected sbs, rows, anaglyph or mono");
}

const char* stereo_mode_name(StereoMode mode) {
    switch (mode) {
    case StereoMode::side_by_side: return "sbs";
    case StereoMode::rows: return "rows";
    case StereoMode::anaglyph: return "anaglyph";
    case StereoMode::mono: return "mono";
    }
    return "?";
}

Result<std::unique_ptr<StereoRenderer>> StereoRenderer::create(VulkanContext& ctx, const RendererOptions& options) {
    if (options.eye_width == 0 || options.eye_height == 0 || options.eye_width > 8192 || options.eye_height > 8192) {
        return make_error(ErrorCode::invalid_argument, "eye size " + std::to_string(options.eye_width) + "x" + std::to_string(options.eye_height) +
                                                           ": expected 1..8192 each");
    }
    if (options.colour_format != VK_FORMAT_R8G8B8A8_UNORM && options.colour_format != VK_FORMAT_B8G8R8A8_UNORM) {
        return make_error(ErrorCode::invalid_argument, "colour format " + std::to_string(options.colour_format) + ": expected R8G8B8A8 or B8G8R8A8 (UNORM)");
    }
    std::unique_ptr<StereoRenderer> r(new StereoRenderer(ctx, options));
    if (r->options_.frames_in_flight == 0) r->options_.frames_in_flight = 1;
    const bool lavapipe = ctx.device_name().find("llvmpipe") != std::string::npos;
    r->multiview_ = options.multiview == RendererOptions::Multiview::on ||
                    (options.multiview == RendererOptions::Multiview::automatic && !lavapipe);
    VkPhysicalDeviceProperties props;
    vkGetPhysicalDeviceProperties(ctx.physical_device(), &props);
    const VkSampleCountFlags usable = props.limits.framebufferColorSampleCounts & props.limits.framebufferDepthSampleCounts;
    for (const VkSampleCountFlagBits s : {VK_SAMPLE_COUNT_8_BIT, VK_SAMPLE_COUNT_4_BIT, VK_SAMPLE_COUNT_2_BIT}) {
        if (static_cast<std::uint32_t>(s) <= options.msaa_samples && (usable & s) != 0) {
            r->samples_ = s;
            break;
        }
    }
    for (auto step : {&StereoRenderer::prepare_frames, &StereoRenderer::prepare_shadow_map, &StereoRenderer::prepare_descriptors,
                      &StereoRenderer::prepare_targets, &StereoRenderer::prepare_pipelines, &StereoRenderer::prepare_builtin_meshes}) {
        if (auto ok = ((*r).*step)(); !ok) return std::move(ok).error();
    }
    return r;
}

StereoRenderer::~StereoRenderer() {
    VkDevice d = ctx_.device();
    vkDeviceWaitIdle(d);
    destroy_targets();
    destroy_image(ctx_, shadow_);
    for (auto& [name, m] : meshes_) destroy_mesh(m);
    for (auto& [name, m] : coarse_meshes_) destroy_mesh(m);
    destroy_image(ctx_, white_texture_);
    destroy_image(ctx_, flat_normal_texture_);
    if (default_material_pool_) vkDestroyDescriptorPool(d, default_material_pool_, nullptr);
    for (auto& f : frames_) {
        destroy_buffer(ctx_, f.uniforms);
        destroy_buffer(ctx_, f.instances);
        destroy_buffer(ctx_, f.readback);
        if (f.fence) vkDestroyFence(d, f.fence, nullptr);
    }
    for (auto& [format, p] : window_composite_) vkDestroyPipeline(d, p, nullptr);
    for (auto& [format, p] : overlay_pipelines_) vkDestroyPipeline(d, p, nullptr);
    if (overlay_layout_) vkDestroyPipelineLayout(d, overlay_layout_, nullptr);
    for (auto& f : frames_) {
        destroy_buffer(ctx_, f.overlay);
        if (f.timestamps) vkDestroyQueryPool(d, f.timestamps, nullptr);
    }
    for (VkSemaphore sem : render_finished_) vkDestroySemaphore(d, sem, nullptr);
    for (auto& f : frames_) {
        if (f.image_available) vkDestroySemaphore(d, f.image_available, nullptr);
    }
    for (VkPipeline p : {scene_pipeline_, per_eye_pipeline_, shadow_pipeline_, composite_pipeline_, translucent_pipeline_, per_eye_translucent_pipeline_,
                         material_pipeline_, per_eye_material_pipeline_, masked_pipeline_, per_eye_masked_pipeline_}) {
        if (p) vkDestroyPipeline(d, p, nullptr);
    }
    for (VkPipelineLayout l : {scene_pipeline_layout_, composite_pipeline_layout_}) {
        if (l) vkDestroyPipelineLayout(d, l, nullptr);
    }
    if (descriptor_pool_) vkDestroyDescriptorPool(d, descriptor_pool_, nullptr);
    for (VkDescriptorSetLayout l : {scene_layout_, composite_layout_, material_layout_}) {
        if (l) vkDestroyDescriptorSetLayout(d, l, nullptr);
    }
    for (auto& [kind, s] : samplers_) vkDestroySampler(d, s, nullptr);
    for (VkSampler s : {shadow_sampler_, eye_sampler_, material_sampler_}) {
        if (s) vkDestroySampler(d, s, nullptr);
    }
    if (pool_) vkDestroyCommandPool(d, pool_, nullptr);
}

Result<void> StereoRenderer::prepare_frames() {
    VkPhysicalDeviceProperties props;
    vkGetPhysicalDeviceProperties(ctx_.physical_device(), &props);
    std::uint32_t families = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(ctx_.physical_device(), &families, nullptr);
    std::vector<VkQueueFamilyProperties> family(families);
    vkGetPhysicalDeviceQueueFamilyProperties(ctx_.physical_device(), &families, family.data());
    const bool can_time = props.limits.timestampComputeAndGraphics || family[ctx_.queue_family()].timestampValidBits > 0;
    timestamp_period_ns_ = can_time ? static_cast<double>(props.limits.timestampPeriod) : 0.0;
    VkCommandPoolCreateInfo pool{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO, nullptr, VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT, ctx_.queue_family()};
    IKEBANA_VK(vkCreateCommandPool(ctx_.device(), &pool, nullptr, &pool_));
    frames_.resize(options_.frames_in_flight);
    for (auto& f : frames_) {
        VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO, nullptr, pool_, VK_COMMAND_BUFFER_LEVEL_PRIMARY, 1};
        IKEBANA_VK(vkAllocateCommandBuffers(ctx_.device(), &alloc, &f.cmd));
        VkFenceCreateInfo fence{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO, nullptr, VK_FENCE_CREATE_SIGNALED_BIT};
        IKEBANA_VK(vkCreateFence(ctx_.device(), &fence, nullptr, &f.fence));
        if (timestamp_period_ns_ > 0.0) {
            VkQueryPoolCreateInfo q{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
            q.queryType = VK_QUERY_TYPE_TIMESTAMP;
            q.queryCount = 4;
            IKEBANA_VK(vkCreateQueryPool(ctx_.device(), &q, nullptr, &f.timestamps));
        }
        auto uniforms = create_buffer(ctx_, sizeof(FrameUniforms), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT);
        if (!uniforms) return std::move(uniforms).error();
        f.uniforms = *uniforms;
    }
    return Ok{};
}

Result<void> StereoRenderer::prepare_shadow_map() {
    auto shadow = create_image(ctx_, depth_format, {options_.shadow_map_size, options_.shadow_map_size}, 1,
                               VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT, VK_IMAGE_ASPECT_DEPTH_BIT);
    if (!shadow) return std::move(shadow).error();
    shadow_ = *shadow;
    VkSamplerCreateInfo s{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
    s.magFilter = s.minFilter = VK_FILTER_LINEAR;
    s.addressModeU = s.addressModeV = s.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_BORDER;
    s.borderColor = VK_BORDER_COLOR_FLOAT_OPAQUE_WHITE;
    s.compareEnable = VK_TRUE;
    s.compareOp = VK_COMPARE_OP_LESS_OR_EQUAL;
    s.maxLod = 0.0f;
    IKEBANA_VK(vkCreateSampler(ctx_.device(), &s, nullptr, &shadow_sampler_));
    VkSamplerCreateInfo e{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
    e.magFilter = e.minFilter = VK_FILTER_NEAREST;
    e.addressModeU = e.addressModeV = e.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
    IKEBANA_VK(vkCreateSampler(ctx_.device(), &e, nullptr, &eye_sampler_));
    return Ok{};
}

VkExtent2D StereoRenderer::output_extent() const noexcept {
    const std::uint32_t area = options_.eye_width + options_.column_px;
    const std::uint32_t w = options_.mode == StereoMode::side_by_side ? 2 * area : area;
    return {w, options_.eye_height};
}

void StereoRenderer::destroy_targets() {
    for (int e = 0; e < 2; ++e) {
        if (eye_layer_[e]) vkDestroyImageView(ctx_.device(), eye_layer_[e], nullptr);
        if (depth_layer_[e]) vkDestroyImageView(ctx_.device(), depth_layer_[e], nullptr);
        if (eye_msaa_layer_[e]) vkDestroyImageView(ctx_.device(), eye_msaa_layer_[e], nullptr);
        eye_layer_[e] = depth_layer_[e] = eye_msaa_layer_[e] = VK_NULL_HANDLE;
    }
    destroy_image(ctx_, eyes_msaa_);
    destroy_image(ctx_, eyes_);
    destroy_image(ctx_, depth_);
    destroy_image(ctx_, output_);
}

// Everything whose size follows the eye size or the stereo mode, and nothing else.
Result<void> StereoRenderer::prepare_targets() {
    const VkExtent2D eye{options_.eye_width, options_.eye_height};
    auto eyes = create_image(ctx_, options_.colour_format, eye, 2,
                             VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT,
                             VK_IMAGE_ASPECT_COLOR_BIT);
    if (!eyes) return std::move(eyes).error();
    eyes_ = *eyes;
    auto depth = create_image(ctx_, depth_format, eye, 2, VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT,
                              VK_IMAGE_ASPECT_DEPTH_BIT, samples_);
    if (!depth) return std::move(depth).error();
    depth_ = *depth;
    if (samples_ != VK_SAMPLE_COUNT_1_BIT) {
        auto msaa = create_image(ctx_, options_.colour_format, eye, 2, VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
                                 VK_IMAGE_ASPECT_COLOR_BIT, samples_);
        if (!msaa) return std::move(msaa).error();
        eyes_msaa_ = *msaa;
    }
    for (std::uint32_t e = 0; e < 2; ++e) {
        VkImageViewCreateInfo view{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
        view.viewType = VK_IMAGE_VIEW_TYPE_2D;
        view.image = eyes_.image;
        view.format = options_.colour_format;
        view.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, e, 1};
        IKEBANA_VK(vkCreateImageView(ctx_.device(), &view, nullptr, &eye_layer_[e]));
        if (eyes_msaa_.image) {
            view.image = eyes_msaa_.image;
            IKEBANA_VK(vkCreateImageView(ctx_.device(), &view, nullptr, &eye_msaa_layer_[e]));
        }
        view.image = depth_.image;
        view.format = depth_format;
        view.subresourceRange = {VK_IMAGE_ASPECT_DEPTH_BIT, 0, 1, e, 1};
        IKEBANA_VK(vkCreateImageView(ctx_.device(), &view, nullptr, &depth_layer_[e]));
    }
    auto output = create_image(ctx_, options_.colour_format, output_extent(), 1,
                               VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT,
                               VK_IMAGE_ASPECT_COLOR_BIT);
    if (!output) return std::move(output).error();
    output_ = *output;
    const VkDeviceSize eye_bytes = 4ull * eye.width * eye.height;
    const VkDeviceSize readback = 4ull * output_.extent.width * output_.extent.height + 2 * eye_bytes;
    for (auto& f : frames_) {
        destroy_buffer(ctx_, f.readback);
        auto buffer = create_buffer(ctx_, readback, VK_BUFFER_USAGE_TRANSFER_DST_BIT);
        if (!buffer) return std::move(buffer).error();
        f.readback = *buffer;
    }
    VkDescriptorImageInfo image{eye_sampler_, eyes_.view, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
    VkWriteDescriptorSet write{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    write.dstSet = composite_set_;
    write.dstBinding = 0;
    write.descriptorCount = 1;
    write.descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
    write.pImageInfo = &image;
    vkUpdateDescriptorSets(ctx_.device(), 1, &write, 0, nullptr);
    return Ok{};
}

Result<void> StereoRenderer::resize(std::uint32_t eye_width, std::uint32_t eye_height) {
    if (eye_width == 0 || eye_height == 0) return make_error(ErrorCode::invalid_argument, "eye size must be positive");
    vkDeviceWaitIdle(ctx_.device());
    destroy_targets();
    options_.eye_width = eye_width;
    options_.eye_height = eye_height;
    return prepare_targets();
}

Result<void> StereoRenderer::set_mode(StereoMode mode) {
    if (mode == options_.mode) return Ok{};
    options_.mode = mode;
    return resize(options_.eye_width, options_.eye_height);
}

Result<void> StereoRenderer::prepare_descriptors() {
    const VkDescriptorSetLayoutBinding scene[2] = {
        {0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 1, VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, nullptr},
        {1, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr}};
    VkDescriptorSetLayoutCreateInfo info{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO, nullptr, 0, 2, scene};
    IKEBANA_VK(vkCreateDescriptorSetLayout(ctx_.device(), &info, nullptr, &scene_layout_));
    const VkDescriptorSetLayoutBinding composite{0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr};
    VkDescriptorSetLayoutCreateInfo cinfo{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO, nullptr, 0, 1, &composite};
    IKEBANA_VK(vkCreateDescriptorSetLayout(ctx_.device(), &cinfo, nullptr, &composite_layout_));
    const VkDescriptorSetLayoutBinding material[2] = {{0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr},
                                                      {1, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr}};
    VkDescriptorSetLayoutCreateInfo minfo{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO, nullptr, 0, 2, material};
    IKEBANA_VK(vkCreateDescriptorSetLayout(ctx_.device(), &minfo, nullptr, &material_layout_));
    const auto n = static_cast<std::uint32_t>(frames_.size());
    const VkDescriptorPoolSize sizes[2] = {{VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, n}, {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, n + 1}};
    VkDescriptorPoolCreateInfo pool{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO, nullptr, 0, n + 1, 2, sizes};
    IKEBANA_VK(vkCreateDescriptorPool(ctx_.device(), &pool, nullptr, &descriptor_pool_));
    for (auto& f : frames_) {
        VkDescriptorSetAllocateInfo alloc{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO, nullptr, descriptor_pool_, 1, &scene_layout_};
        IKEBANA_VK(vkAllocateDescriptorSets(ctx_.device(), &alloc, &f.scene_set));
        VkDescriptorBufferInfo ubo{f.uniforms.buffer, 0, sizeof(FrameUniforms)};
        VkDescriptorImageInfo shadow{shadow_sampler_, shadow_.view, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
        VkWriteDescriptorSet writes[2] = {{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET}, {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET}};
        writes[0].dstSet = f.scene_set;
        writes[0].dstBinding = 0;
        writes[0].descriptorCount = 1;
        writes[0].descriptorType = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
        writes[0].pBufferInfo = &ubo;
        writes[1].dstSet = f.scene_set;
        writes[1].dstBinding = 1;
        writes[1].descriptorCount = 1;
        writes[1].descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
        writes[1].pImageInfo = &shadow;
        vkUpdateDescriptorSets(ctx_.device(), 2, writes, 0, nullptr);
    }
    VkDescriptorSetAllocateInfo alloc{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO, nullptr, descriptor_pool_, 1, &composite_layout_};
    IKEBANA_VK(vkAllocateDescriptorSets(ctx_.device(), &alloc, &composite_set_));
    return Ok{};
}

Result<StereoRenderer::Frame*> StereoRenderer::begin_frame(const DrawList& list, const StereoRig& rig_in) {
    Frame& frame = frames_[frame_index_];
    frame_index_ = (frame_index_ + 1) % frames_.size();
    IKEBANA_VK(vkWaitForFences(ctx_.device(), 1, &frame.fence, VK_TRUE, UINT64_MAX));

    // Instances of every batch in one buffer, each batch drawn from its offset.
    std::vector<MeshInstance> instances;
    draws_.clear();
    // Level of detail from the rig's centre: each batch's instances that are large on screen first, with
    // their mesh, then the small ones with its coarse copy (the shadow map's texels, 0.8 mm, are about
    // the eyes' pixels at arm's length, so the shadow pass takes the same split).
    const double focal_px = static_cast<double>(options_.eye_height) / (2.0 * std::tan(0.5 * rig_in.vertical_fov_rad));
    for (const auto& batch : list.batches) {
        if (batch.instances.empty()) continue;
        auto m = mesh(batch.mesh);
        if (!m) return std::move(m).error();
        const bool shadow = batch.casts_shadow && !batch.translucent;
        const auto start = static_cast<std::ptrdiff_t>(instances.size());
        instances.insert(instances.end(), batch.instances.begin(), batch.instances.end());
        auto small = instances.end();
        if ((*m)->coarse && options_.coarse_below_px > 0.0) {
            small = std::stable_partition(instances.begin() + start, instances.end(), [&](const MeshInstance& i) {
                return screen_length_px(i.model, (*m)->span, rig_in.position_m, focal_px) >= options_.coarse_below_px;
            });
        }
        const auto large_count = static_cast<std::uint32_t>(small - (instances.begin() + start));
        const auto small_count = static_cast<std::uint32_t>(instances.end() - small);
        if (large_count > 0) draws_.push_back({*m, large_count, shadow, batch.translucent});
        if (small_count > 0) draws_.push_back({(*m)->coarse, small_count, shadow, batch.translucent});
    }
    eye_triangles_ = shadow_triangles_ = 0;
    for (const auto& d : draws_) {
        const std::uint64_t triangles = std::uint64_t{d.mesh->index_count / 3} * d.instances;
        eye_triangles_ += triangles;
        if (d.casts_shadow) shadow_triangles_ += triangles;
    }
    const VkDeviceSize needed = std::max<VkDeviceSize>(1, instances.size()) * sizeof(MeshInstance);
    if (frame.instances.size < needed) {
        destroy_buffer(ctx_, frame.instances);
        auto buffer = create_buffer(ctx_, needed * 2, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT);
        if (!buffer) return std::move(buffer).error();
        frame.instances = *buffer;
    }
    if (!instances.empty()) std::memcpy(frame.instances.mapped, instances.data(), instances.size() * sizeof(MeshInstance));

    StereoRig rig = rig_in;
    rig.aspect = static_cast<double>(options_.eye_width) / static_cast<double>(options_.eye_height);
    if (options_.mode == StereoMode::mono) rig.eye_separation_m = 0.0;
    FrameUniforms u{};
    u.view_projection[0] = eye_matrices(rig, -1).view_projection;
    u.view_projection[1] = eye_matrices(rig, +1).view_projection;
    u.light_view_projection = light_matrix(list);
    u.light_direction = glm::vec4(glm::normalize(list.light_direction), 0.0f);
    u.eye_position[0] = glm::vec4(glm::vec3(eye_matrices(rig, -1).eye_position_m), 1.0f);
    u.eye_position[1] = glm::vec4(glm::vec3(eye_matrices(rig, +1).eye_position_m), 1.0f);
    std::memcpy(frame.uniforms.mapped, &u, sizeof u);

    if (auto o = fill_overlay(frame); !o) return std::move(o).error();
    const glm::vec2 eye_px{static_cast<float>(options_.eye_width), static_cast<float>(options_.eye_height)};
    const bool two_areas = options_.mode == StereoMode::side_by_side;
    const glm::mat4 centre = eye_matrices(rig, 0).view_projection;
    frame.overlay_origins.clear();
    for (const auto& panel : overlay_) {
        frame.overlay_origins.push_back({overlay_origin_px(panel, two_areas ? u.view_projection[0] : centre, eye_px),
                                         overlay_origin_px(panel, two_areas ? u.view_projection[1] : centre, eye_px)});
    }
    IKEBANA_VK(vkResetCommandBuffer(frame.cmd, 0));
    VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO, nullptr, VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT, nullptr};
    IKEBANA_VK(vkBeginCommandBuffer(frame.cmd, &begin));
    return &frame;
}

Result<RenderedFrame> StereoRenderer::render(const DrawList& list, const StereoRig& rig, bool with_eyes) {
    const auto started = std::chrono::steady_clock::now();
    auto begun = begin_frame(list, rig);
    if (!begun) return std::move(begun).error();
    Frame& frame = **begun;
    auto overlay = overlay_pipeline_for(options_.colour_format);
    if (!overlay) return std::move(overlay).error();
    record(frame, list, draws_, {output_.image, output_.view, output_.extent, composite_pipeline_, *overlay, true, with_eyes, false, true, options_.colour_format});
    IKEBANA_VK(vkEndCommandBuffer(frame.cmd));
    IKEBANA_VK(vkResetFences(ctx_.device(), 1, &frame.fence));
    RenderedFrame out;
    out.timing.record_ms = ms_since(started);
    out.timing.eye_triangles = eye_triangles_;
    out.timing.shadow_triangles = shadow_triangles_;

    const auto submitted = std::chrono::steady_clock::now();
    VkCommandBufferSubmitInfo cmd_info{VK_STRUCTURE_TYPE_COMMAND_BUFFER_SUBMIT_INFO, nullptr, frame.cmd, 0};
    VkSubmitInfo2 submit{VK_STRUCTURE_TYPE_SUBMIT_INFO_2};
    submit.commandBufferInfoCount = 1;
    submit.pCommandBufferInfos = &cmd_info;
    IKEBANA_VK(vkQueueSubmit2(ctx_.queue(), 1, &submit, frame.fence));
    IKEBANA_VK(vkWaitForFences(ctx_.device(), 1, &frame.fence, VK_TRUE, UINT64_MAX));
    out.timing.execute_ms = ms_since(submitted);
    read_timestamps(frame, out.timing);

    const auto copied = std::chrono::steady_clock::now();
    const VkExtent2D o = output_.extent;
    const bool bgra = options_.colour_format == VK_FORMAT_B8G8R8A8_UNORM;
    read_back(frame, out.composed, o, 0, bgra);
    if (with_eyes) {
        const std::size_t eye_bytes = 4ull * options_.eye_width * options_.eye_height;
        read_back(frame, out.left, eyes_.extent, 4ull * o.width * o.height, bgra);
        read_back(frame, out.right, eyes_.extent, 4ull * o.width * o.height + eye_bytes, bgra);
    }
    out.timing.readback_ms = ms_since(copied);
    return out;
}

void StereoRenderer::read_timestamps(Frame& frame, FrameTiming& timing) const {
    if (!frame.timestamps || !frame.timestamps_written) return;
    std::uint64_t t[4] = {};
    if (vkGetQueryPoolResults(ctx_.device(), frame.timestamps, 0, 4, sizeof t, t, sizeof(std::uint64_t), VK_QUERY_RESULT_64_BIT) != VK_SUCCESS) return;
    const double ms = timestamp_period_ns_ * 1e-6;
    timing.shadow_ms = static_cast<double>(t[1] - t[0]) * ms;
    timing.scene_ms = static_cast<double>(t[2] - t[1]) * ms;
    timing.composite_ms = static_cast<double>(t[3] - t[2]) * ms;
}

void StereoRenderer::read_back(const Frame& frame, RgbaImage& img, VkExtent2D extent, std::size_t offset, bool bgra) const {
    const auto* bytes = static_cast<const std::uint8_t*>(frame.readback.mapped);
    img.width = extent.width;
    img.height = extent.height;
    img.pixels.assign(bytes + offset, bytes + offset + 4ull * extent.width * extent.height);
    if (bgra) {
        for (std::size_t i = 0; i < img.pixels.size(); i += 4) std::swap(img.pixels[i], img.pixels[i + 2]);
    }
}

Result<PresentedFrame> StereoRenderer::present(Swapchain& swapchain, const DrawList& list, const StereoRig& rig, bool screenshot) {
    PresentedFrame result;
    const VkExtent2D window = swapchain.extent();
    // The eyes follow the window, beside the column kept for panels: only the size-dependent targets
    // are rebuilt.
    const ScreenLayout layout{options_.mode, {window.width, window.height}, static_cast<double>(options_.column_px)};
    const auto eye_w = static_cast<std::uint32_t>(layout.scene_width_px());
    if (eye_w != options_.eye_width || window.height != options_.eye_height || eye_w + options_.column_px != static_cast<std::uint32_t>(layout.area_width_px())) {
        options_.column_px = static_cast<std::uint32_t>(layout.area_width_px()) - eye_w; // what is left of the area
        if (auto r = resize(eye_w, window.height); !r) return std::move(r).error();
    }
    auto pipeline = composite_pipeline_for(swapchain.format());
    if (!pipeline) return std::move(pipeline).error();
    const auto started = std::chrono::steady_clock::now();
    auto begun = begin_frame(list, rig);
    if (!begun) return std::move(begun).error();
    Frame& frame = **begun;
    read_timestamps(frame, result.timing); // this slot's previous frame: its fence has been waited for
    if (frame.image_available == VK_NULL_HANDLE) {
        VkSemaphoreCreateInfo info{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
        IKEBANA_VK(vkCreateSemaphore(ctx_.device(), &info, nullptr, &frame.image_available));
    }
    auto image = swapchain.acquire(frame.image_available);
    if (!image) return std::move(image).error();
    if (!*image) {
        vkEndCommandBuffer(frame.cmd);
        result.swapchain_stale = true;
        return result;
    }
    const std::uint32_t index = **image;
    while (render_finished_.size() < swapchain.image_count()) {
        VkSemaphoreCreateInfo info{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
        VkSemaphore s = VK_NULL_HANDLE;
        IKEBANA_VK(vkCreateSemaphore(ctx_.device(), &info, nullptr, &s));
        render_finished_.push_back(s);
    }
    const bool copy = screenshot && swapchain.can_copy_from();
    auto overlay = overlay_pipeline_for(swapchain.format());
    if (!overlay) return std::move(overlay).error();
    record(frame, list, draws_, {swapchain.image(index), swapchain.view(index), window, *pipeline, *overlay, copy, false, true, swapchain.can_copy_to(), swapchain.format()});
    IKEBANA_VK(vkEndCommandBuffer(frame.cmd));
    IKEBANA_VK(vkResetFences(ctx_.device(), 1, &frame.fence));
    result.timing.record_ms = ms_since(started);
    result.timing.eye_triangles = eye_triangles_;
    result.timing.shadow_triangles = shadow_triangles_;
    VkSemaphoreSubmitInfo wait{VK_STRUCTURE_TYPE_SEMAPHORE_SUBMIT_INFO, nullptr, frame.image_available, 0,
                               VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, 0};
    VkSemaphoreSubmitInfo signal{VK_STRUCTURE_TYPE_SEMAPHORE_SUBMIT_INFO, nullptr, render_finished_[index], 0,
                                 VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, 0};
    VkCommandBufferSubmitInfo cmd_info{VK_STRUCTURE_TYPE_COMMAND_BUFFER_SUBMIT_INFO, nullptr, frame.cmd, 0};
    VkSubmitInfo2 submit{VK_STRUCTURE_TYPE_SUBMIT_INFO_2};
    submit.waitSemaphoreInfoCount = 1;
    submit.pWaitSemaphoreInfos = &wait;
    submit.commandBufferInfoCount = 1;
    submit.pCommandBufferInfos = &cmd_info;
    submit.signalSemaphoreInfoCount = 1;
    submit.pSignalSemaphoreInfos = &signal;
    const auto submitted = std::chrono::steady_clock::now();
    IKEBANA_VK(vkQueueSubmit2(ctx_.queue(), 1, &submit, frame.fence));
    const auto presenting = std::chrono::steady_clock::now();
    auto presented = swapchain.present(index, render_finished_[index]);
    result.timing.present_ms = ms_since(presenting);
    if (!presented) return std::move(presented).error();
    result.presented = true;
    result.swapchain_stale = !*presented;
    if (copy) {
        IKEBANA_VK(vkWaitForFences(ctx_.device(), 1, &frame.fence, VK_TRUE, UINT64_MAX));
        RgbaImage shot;
        const bool bgra = swapchain.format() == VK_FORMAT_B8G8R8A8_UNORM || swapchain.format() == VK_FORMAT_B8G8R8A8_SRGB;
        read_back(frame, shot, window, 0, bgra);
        result.screenshot = std::move(shot);
    }
    result.timing.execute_ms = ms_since(submitted);
    return result;
}

} // namespace ikebana::render
