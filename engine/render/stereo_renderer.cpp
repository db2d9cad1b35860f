#include "engine/render/stereo_renderer.hpp"

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>

#include "engine/render/builtin_meshes.hpp"

namespace ikebana::render {

namespace {

constexpr VkFormat depth_format = VK_FORMAT_D32_SFLOAT;

struct FrameUniforms {
    glm::mat4 view_projection[2];
    glm::mat4 light_view_projection;
    glm::vec4 light_direction;
};

struct Vertex {
    glm::vec3 position;
    glm::vec3 normal;
};

struct OverlayConstants {
    float target_width, target_height;
    float offset_x, offset_y;
    float scale;
};

struct CompositeConstants {
    std::int32_t mode;
    std::int32_t eye_width;
    std::int32_t eye_height;
    std::int32_t first_row_eye;
};

#define IKEBANA_VK(call)                                                                                                                  \
    do {                                                                                                                                   \
        if (VkResult vk_result_ = (call); vk_result_ != VK_SUCCESS) return vulkan_error(#call, vk_result_);                               \
    } while (false)

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
    for (auto& [name, m] : meshes_) {
        destroy_buffer(ctx_, m.vertices);
        destroy_buffer(ctx_, m.indices);
    }
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
    for (VkPipeline p : {scene_pipeline_, per_eye_pipeline_, shadow_pipeline_, composite_pipeline_}) {
        if (p) vkDestroyPipeline(d, p, nullptr);
    }
    for (VkPipelineLayout l : {scene_pipeline_layout_, composite_pipeline_layout_}) {
        if (l) vkDestroyPipelineLayout(d, l, nullptr);
    }
    if (descriptor_pool_) vkDestroyDescriptorPool(d, descriptor_pool_, nullptr);
    for (VkDescriptorSetLayout l : {scene_layout_, composite_layout_}) {
        if (l) vkDestroyDescriptorSetLayout(d, l, nullptr);
    }
    for (VkSampler s : {shadow_sampler_, eye_sampler_}) {
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
    const std::uint32_t w = options_.mode == StereoMode::side_by_side ? 2 * options_.eye_width : options_.eye_width;
    return {w, options_.eye_height};
}

void StereoRenderer::destroy_targets() {
    for (int e = 0; e < 2; ++e) {
        if (eye_layer_[e]) vkDestroyImageView(ctx_.device(), eye_layer_[e], nullptr);
        if (depth_layer_[e]) vkDestroyImageView(ctx_.device(), depth_layer_[e], nullptr);
        eye_layer_[e] = depth_layer_[e] = VK_NULL_HANDLE;
    }
    destroy_image(ctx_, eyes_);
    destroy_image(ctx_, depth_);
    destroy_image(ctx_, output_);
}

// Everything whose size follows the eye size or the stereo mode, and nothing else.
Result<void> StereoRenderer::prepare_targets() {
    const VkExtent2D eye{options_.eye_width, options_.eye_height};
    auto eyes = create_image(ctx_, options_.colour_format, eye, 2,
                             VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT, VK_IMAGE_ASPECT_COLOR_BIT);
    if (!eyes) return std::move(eyes).error();
    eyes_ = *eyes;
    auto depth = create_image(ctx_, depth_format, eye, 2, VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT,
                              VK_IMAGE_ASPECT_DEPTH_BIT);
    if (!depth) return std::move(depth).error();
    depth_ = *depth;
    for (std::uint32_t e = 0; e < 2; ++e) {
        VkImageViewCreateInfo view{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
        view.viewType = VK_IMAGE_VIEW_TYPE_2D;
        view.image = eyes_.image;
        view.format = options_.colour_format;
        view.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, e, 1};
        IKEBANA_VK(vkCreateImageView(ctx_.device(), &view, nullptr, &eye_layer_[e]));
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

Result<void> StereoRenderer::prepare_pipelines() {
    VkShaderModule modules[3] = {};
    const char* names[3] = {"mesh.vert.spv", "mesh.frag.spv", "shadow.vert.spv"};
    for (int i = 0; i < 3; ++i) {
        auto m = load_shader(ctx_, options_.shader_dir / names[i]);
        if (!m) {
            for (VkShaderModule done : modules) {
                if (done) vkDestroyShaderModule(ctx_.device(), done, nullptr);
            }
            return std::move(m).error();
        }
        modules[i] = *m;
    }
    struct Cleanup {
        VkDevice d;
        VkShaderModule* m;
        ~Cleanup() {
            for (int i = 0; i < 3; ++i) vkDestroyShaderModule(d, m[i], nullptr);
        }
    } cleanup{ctx_.device(), modules};

    const VkPushConstantRange eye_push{VK_SHADER_STAGE_VERTEX_BIT, 0, sizeof(std::int32_t)};
    VkPipelineLayoutCreateInfo scene_layout{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO, nullptr, 0, 1, &scene_layout_, 1, &eye_push};
    IKEBANA_VK(vkCreatePipelineLayout(ctx_.device(), &scene_layout, nullptr, &scene_pipeline_layout_));
    const VkPushConstantRange push{VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof(CompositeConstants)};
    VkPipelineLayoutCreateInfo composite_layout{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO, nullptr, 0, 1, &composite_layout_, 1, &push};
    IKEBANA_VK(vkCreatePipelineLayout(ctx_.device(), &composite_layout, nullptr, &composite_pipeline_layout_));

    const VkVertexInputBindingDescription bindings[2] = {{0, sizeof(Vertex), VK_VERTEX_INPUT_RATE_VERTEX},
                                                         {1, sizeof(MeshInstance), VK_VERTEX_INPUT_RATE_INSTANCE}};
    const VkVertexInputAttributeDescription attributes[7] = {
        {0, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(Vertex, position)}, {1, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(Vertex, normal)},
        {2, 1, VK_FORMAT_R32G32B32A32_SFLOAT, 0},                       {3, 1, VK_FORMAT_R32G32B32A32_SFLOAT, 16},
        {4, 1, VK_FORMAT_R32G32B32A32_SFLOAT, 32},                      {5, 1, VK_FORMAT_R32G32B32A32_SFLOAT, 48},
        {6, 1, VK_FORMAT_R32G32B32A32_SFLOAT, offsetof(MeshInstance, colour)}};
    VkPipelineVertexInputStateCreateInfo vertex_input{VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO, nullptr, 0, 2, bindings, 7, attributes};
    VkPipelineInputAssemblyStateCreateInfo assembly{VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO, nullptr, 0,
                                                    VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST, VK_FALSE};
    VkPipelineViewportStateCreateInfo viewport{VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO, nullptr, 0, 1, nullptr, 1, nullptr};
    VkPipelineRasterizationStateCreateInfo raster{VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO};
    raster.polygonMode = VK_POLYGON_MODE_FILL;
    raster.cullMode = VK_CULL_MODE_NONE; // petals and leaves are single sheets
    raster.frontFace = VK_FRONT_FACE_COUNTER_CLOCKWISE;
    raster.lineWidth = 1.0f;
    VkPipelineMultisampleStateCreateInfo multisample{VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO};
    multisample.rasterizationSamples = VK_SAMPLE_COUNT_1_BIT;
    VkPipelineDepthStencilStateCreateInfo depth{VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO};
    depth.depthTestEnable = VK_TRUE;
    depth.depthWriteEnable = VK_TRUE;
    depth.depthCompareOp = VK_COMPARE_OP_LESS;
    VkPipelineColorBlendAttachmentState blend_attachment{};
    blend_attachment.colorWriteMask = VK_COLOR_COMPONENT_R_BIT | VK_COLOR_COMPONENT_G_BIT | VK_COLOR_COMPONENT_B_BIT | VK_COLOR_COMPONENT_A_BIT;
    VkPipelineColorBlendStateCreateInfo blend{VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO};
    blend.attachmentCount = 1;
    blend.pAttachments = &blend_attachment;
    VkPipelineColorBlendStateCreateInfo no_blend{VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO};
    // Culling is set per batch (closed meshes cull their back faces; sheets do not).
    const VkDynamicState dynamic_states[3] = {VK_DYNAMIC_STATE_VIEWPORT, VK_DYNAMIC_STATE_SCISSOR, VK_DYNAMIC_STATE_CULL_MODE};
    VkPipelineDynamicStateCreateInfo dynamic{VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO, nullptr, 0, 3, dynamic_states};
    auto stage = [](VkShaderStageFlagBits s, VkShaderModule m) {
        return VkPipelineShaderStageCreateInfo{VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO, nullptr, 0, s, m, "main", nullptr};
    };

    // Scene: both eyes at once.
    VkPipelineRenderingCreateInfo scene_rendering{VK_STRUCTURE_TYPE_PIPELINE_RENDERING_CREATE_INFO};
    scene_rendering.viewMask = 0b11;
    scene_rendering.colorAttachmentCount = 1;
    scene_rendering.pColorAttachmentFormats = &options_.colour_format;
    scene_rendering.depthAttachmentFormat = depth_format;
    const VkPipelineShaderStageCreateInfo scene_stages[2] = {stage(VK_SHADER_STAGE_VERTEX_BIT, modules[0]), stage(VK_SHADER_STAGE_FRAGMENT_BIT, modules[1])};
    VkGraphicsPipelineCreateInfo info{VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO};
    info.pNext = &scene_rendering;
    info.stageCount = 2;
    info.pStages = scene_stages;
    info.pVertexInputState = &vertex_input;
    info.pInputAssemblyState = &assembly;
    info.pViewportState = &viewport;
    info.pRasterizationState = &raster;
    info.pMultisampleState = &multisample;
    info.pDepthStencilState = &depth;
    info.pColorBlendState = &blend;
    info.pDynamicState = &dynamic;
    info.layout = scene_pipeline_layout_;
    IKEBANA_VK(vkCreateGraphicsPipelines(ctx_.device(), VK_NULL_HANDLE, 1, &info, nullptr, &scene_pipeline_));
    scene_rendering.viewMask = 0; // the same, one eye per pass
    IKEBANA_VK(vkCreateGraphicsPipelines(ctx_.device(), VK_NULL_HANDLE, 1, &info, nullptr, &per_eye_pipeline_));

    // Shadow: depth only, from the light, with a slope bias against acne.
    VkPipelineRenderingCreateInfo shadow_rendering{VK_STRUCTURE_TYPE_PIPELINE_RENDERING_CREATE_INFO};
    shadow_rendering.depthAttachmentFormat = depth_format;
    VkPipelineRasterizationStateCreateInfo shadow_raster = raster;
    shadow_raster.depthBiasEnable = VK_TRUE;
    shadow_raster.depthBiasConstantFactor = 1.25f;
    shadow_raster.depthBiasSlopeFactor = 1.75f;
    const VkPipelineShaderStageCreateInfo shadow_stage = stage(VK_SHADER_STAGE_VERTEX_BIT, modules[2]);
    // Positions and model matrices only: normals and colours mean nothing to depth.
    const VkVertexInputAttributeDescription shadow_attributes[5] = {attributes[0], attributes[2], attributes[3], attributes[4], attributes[5]};
    VkPipelineVertexInputStateCreateInfo shadow_input{VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO, nullptr, 0, 2, bindings, 5,
                                                      shadow_attributes};
    info.pVertexInputState = &shadow_input;
    info.pNext = &shadow_rendering;
    info.stageCount = 1;
    info.pStages = &shadow_stage;
    info.pRasterizationState = &shadow_raster;
    info.pColorBlendState = &no_blend;
    IKEBANA_VK(vkCreateGraphicsPipelines(ctx_.device(), VK_NULL_HANDLE, 1, &info, nullptr, &shadow_pipeline_));

    auto composite = make_composite_pipeline(options_.colour_format);
    if (!composite) return std::move(composite).error();
    composite_pipeline_ = *composite;
    return Ok{};
}

// A screen-space pipeline (no depth, no culling) drawing into one colour target of this format: the
// composite and the heads-up display differ only in their shaders, vertex input, blending and layout.
Result<VkPipeline> StereoRenderer::make_screen_pipeline(VkFormat format, const char* shader, const VkPipelineVertexInputStateCreateInfo& input,
                                                        const VkPipelineColorBlendAttachmentState& blend_attachment, VkPipelineLayout layout) {
    auto vert = load_shader(ctx_, options_.shader_dir / (std::string(shader) + ".vert.spv"));
    if (!vert) return std::move(vert).error();
    auto frag = load_shader(ctx_, options_.shader_dir / (std::string(shader) + ".frag.spv"));
    if (!frag) {
        vkDestroyShaderModule(ctx_.device(), *vert, nullptr);
        return std::move(frag).error();
    }
    VkPipelineInputAssemblyStateCreateInfo assembly{VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO, nullptr, 0,
                                                    VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST, VK_FALSE};
    VkPipelineViewportStateCreateInfo viewport{VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO, nullptr, 0, 1, nullptr, 1, nullptr};
    VkPipelineRasterizationStateCreateInfo raster{VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO};
    raster.polygonMode = VK_POLYGON_MODE_FILL;
    raster.cullMode = VK_CULL_MODE_NONE;
    raster.lineWidth = 1.0f;
    VkPipelineMultisampleStateCreateInfo multisample{VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO};
    multisample.rasterizationSamples = VK_SAMPLE_COUNT_1_BIT;
    VkPipelineDepthStencilStateCreateInfo no_depth{VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO};
    VkPipelineColorBlendStateCreateInfo blend{VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO};
    blend.attachmentCount = 1;
    blend.pAttachments = &blend_attachment;
    const VkDynamicState dynamic_states[2] = {VK_DYNAMIC_STATE_VIEWPORT, VK_DYNAMIC_STATE_SCISSOR};
    VkPipelineDynamicStateCreateInfo dynamic{VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO, nullptr, 0, 2, dynamic_states};
    VkPipelineRenderingCreateInfo rendering{VK_STRUCTURE_TYPE_PIPELINE_RENDERING_CREATE_INFO};
    rendering.colorAttachmentCount = 1;
    rendering.pColorAttachmentFormats = &format;
    const VkPipelineShaderStageCreateInfo stages[2] = {
        {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO, nullptr, 0, VK_SHADER_STAGE_VERTEX_BIT, *vert, "main", nullptr},
        {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO, nullptr, 0, VK_SHADER_STAGE_FRAGMENT_BIT, *frag, "main", nullptr}};
    VkGraphicsPipelineCreateInfo info{VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO};
    info.pNext = &rendering;
    info.stageCount = 2;
    info.pStages = stages;
    info.pVertexInputState = &input;
    info.pInputAssemblyState = &assembly;
    info.pViewportState = &viewport;
    info.pRasterizationState = &raster;
    info.pMultisampleState = &multisample;
    info.pDepthStencilState = &no_depth;
    info.pColorBlendState = &blend;
    info.pDynamicState = &dynamic;
    info.layout = layout;
    VkPipeline pipeline = VK_NULL_HANDLE;
    const VkResult r = vkCreateGraphicsPipelines(ctx_.device(), VK_NULL_HANDLE, 1, &info, nullptr, &pipeline);
    vkDestroyShaderModule(ctx_.device(), *vert, nullptr);
    vkDestroyShaderModule(ctx_.device(), *frag, nullptr);
    if (r != VK_SUCCESS) return vulkan_error((std::string("vkCreateGraphicsPipelines (") + shader + ")").c_str(), r);
    return pipeline;
}

// Composite: one triangle, the eyes to an output of this format (offscreen, or the window's).
Result<VkPipeline> StereoRenderer::make_composite_pipeline(VkFormat format) {
    const VkPipelineVertexInputStateCreateInfo no_input{VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO};
    VkPipelineColorBlendAttachmentState opaque{};
    opaque.colorWriteMask = VK_COLOR_COMPONENT_R_BIT | VK_COLOR_COMPONENT_G_BIT | VK_COLOR_COMPONENT_B_BIT | VK_COLOR_COMPONENT_A_BIT;
    return make_screen_pipeline(format, "composite", no_input, opaque, composite_pipeline_layout_);
}

// Heads-up panels: pixel-space triangles with their own colours, alpha-blended over the frame.
Result<VkPipeline> StereoRenderer::make_overlay_pipeline(VkFormat format) {
    if (!overlay_layout_) {
        const VkPushConstantRange push{VK_SHADER_STAGE_VERTEX_BIT, 0, sizeof(OverlayConstants)};
        VkPipelineLayoutCreateInfo layout{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO, nullptr, 0, 0, nullptr, 1, &push};
        IKEBANA_VK(vkCreatePipelineLayout(ctx_.device(), &layout, nullptr, &overlay_layout_));
    }
    const VkVertexInputBindingDescription binding{0, sizeof(OverlayVertex), VK_VERTEX_INPUT_RATE_VERTEX};
    const VkVertexInputAttributeDescription attributes[2] = {{0, 0, VK_FORMAT_R32G32B32_SFLOAT, 0},
                                                             {1, 0, VK_FORMAT_R8G8B8A8_UNORM, offsetof(OverlayVertex, colour)}};
    const VkPipelineVertexInputStateCreateInfo input{VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO, nullptr, 0, 1, &binding, 2, attributes};
    VkPipelineColorBlendAttachmentState alpha{};
    alpha.blendEnable = VK_TRUE;
    alpha.srcColorBlendFactor = VK_BLEND_FACTOR_SRC_ALPHA;
    alpha.dstColorBlendFactor = VK_BLEND_FACTOR_ONE_MINUS_SRC_ALPHA;
    alpha.colorBlendOp = VK_BLEND_OP_ADD;
    alpha.srcAlphaBlendFactor = VK_BLEND_FACTOR_ONE;
    alpha.dstAlphaBlendFactor = VK_BLEND_FACTOR_ONE_MINUS_SRC_ALPHA;
    alpha.alphaBlendOp = VK_BLEND_OP_ADD;
    alpha.colorWriteMask = VK_COLOR_COMPONENT_R_BIT | VK_COLOR_COMPONENT_G_BIT | VK_COLOR_COMPONENT_B_BIT | VK_COLOR_COMPONENT_A_BIT;
    return make_screen_pipeline(format, "overlay", input, alpha, overlay_layout_);
}

// No panels: no pipeline (and nothing drawn).
Result<VkPipeline> StereoRenderer::overlay_pipeline_for(VkFormat format) {
    if (overlay_.empty()) return VkPipeline{VK_NULL_HANDLE};
    return cached_pipeline(overlay_pipelines_, format, &StereoRenderer::make_overlay_pipeline);
}

// One pipeline per output format, made on first use.
Result<VkPipeline> StereoRenderer::cached_pipeline(std::map<VkFormat, VkPipeline>& cache, VkFormat format,
                                                   Result<VkPipeline> (StereoRenderer::*make)(VkFormat)) {
    if (auto it = cache.find(format); it != cache.end()) return it->second;
    auto made = (this->*make)(format);
    if (!made) return std::move(made).error();
    cache[format] = *made;
    return *made;
}

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

Result<StereoRenderer::Frame*> StereoRenderer::begin_frame(const DrawList& list, const StereoRig& rig_in) {
    Frame& frame = frames_[frame_index_];
    frame_index_ = (frame_index_ + 1) % frames_.size();
    IKEBANA_VK(vkWaitForFences(ctx_.device(), 1, &frame.fence, VK_TRUE, UINT64_MAX));

    // Instances of every batch in one buffer, each batch drawn from its offset.
    std::vector<MeshInstance> instances;
    draws_.clear();
    for (const auto& batch : list.batches) {
        if (batch.instances.empty()) continue;
        auto m = mesh(batch.mesh);
        if (!m) return std::move(m).error();
        draws_.push_back({*m, static_cast<std::uint32_t>(batch.instances.size()), batch.casts_shadow});
        instances.insert(instances.end(), batch.instances.begin(), batch.instances.end());
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
    std::memcpy(frame.uniforms.mapped, &u, sizeof u);

    if (auto o = fill_overlay(frame); !o) return std::move(o).error();
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

Result<VkPipeline> StereoRenderer::composite_pipeline_for(VkFormat format) {
    if (format == options_.colour_format) return composite_pipeline_;
    return cached_pipeline(window_composite_, format, &StereoRenderer::make_composite_pipeline);
}

Result<PresentedFrame> StereoRenderer::present(Swapchain& swapchain, const DrawList& list, const StereoRig& rig, bool screenshot) {
    PresentedFrame result;
    const VkExtent2D window = swapchain.extent();
    const std::uint32_t eye_w = options_.mode == StereoMode::side_by_side ? std::max(1u, window.width / 2) : window.width;
    if (eye_w != options_.eye_width || window.height != options_.eye_height || output_extent().width != window.width) {
        // The eyes follow the window: only the size-dependent targets are rebuilt.
        if (auto r = resize(eye_w, window.height); !r) return std::move(r).error();
        if (output_extent().width != window.width) {
            options_.eye_width = window.width / 2;
            if (auto r = resize(options_.eye_width, window.height); !r) return std::move(r).error();
        }
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

void StereoRenderer::record(Frame& frame, const DrawList& list, const std::vector<Draw>& draws, const CompositeTarget& target) {
    const bool with_eyes = target.with_eyes;
    VkCommandBuffer cmd = frame.cmd;
    auto draw_all = [&](bool shadow_casters_only) {
        VkDeviceSize zero = 0;
        std::uint32_t first = 0;
        for (const auto& d : draws) {
            // Each batch's instances from its offset in the frame's instance buffer.
            if (!shadow_casters_only || d.casts_shadow) {
                VkBuffer buffers[2] = {d.mesh->vertices.buffer, frame.instances.buffer};
                VkDeviceSize offsets[2] = {zero, first * sizeof(MeshInstance)};
                vkCmdBindVertexBuffers(cmd, 0, 2, buffers, offsets);
                vkCmdBindIndexBuffer(cmd, d.mesh->indices.buffer, 0, VK_INDEX_TYPE_UINT32);
                vkCmdSetCullMode(cmd, d.mesh->closed ? VK_CULL_MODE_BACK_BIT : VK_CULL_MODE_NONE);
                vkCmdDrawIndexed(cmd, d.mesh->index_count, d.instances, 0, 0, 0);
            }
            first += d.instances;
        }
    };
    auto set_viewport = [&](VkExtent2D e) {
        VkViewport v{0.0f, 0.0f, static_cast<float>(e.width), static_cast<float>(e.height), 0.0f, 1.0f};
        VkRect2D s{{0, 0}, e};
        vkCmdSetViewport(cmd, 0, 1, &v);
        vkCmdSetScissor(cmd, 0, 1, &s);
    };
    constexpr auto none = VK_PIPELINE_STAGE_2_NONE;
    if (frame.timestamps) {
        vkCmdResetQueryPool(cmd, frame.timestamps, 0, 4);
        vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_TOP_OF_PIPE_BIT, frame.timestamps, 0);
    }
    // 1. Shadow map.
    transition(cmd, shadow_.image, VK_IMAGE_ASPECT_DEPTH_BIT, 1, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL,
               VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, 0, VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT,
               VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT);
    VkRenderingAttachmentInfo shadow_depth{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
    shadow_depth.imageView = shadow_.view;
    shadow_depth.imageLayout = VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL;
    shadow_depth.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
    shadow_depth.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    shadow_depth.clearValue.depthStencil = {1.0f, 0};
    VkRenderingInfo shadow_pass{VK_STRUCTURE_TYPE_RENDERING_INFO};
    shadow_pass.renderArea = {{0, 0}, shadow_.extent};
    shadow_pass.layerCount = 1;
    shadow_pass.pDepthAttachment = &shadow_depth;
    vkCmdBeginRendering(cmd, &shadow_pass);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, shadow_pipeline_);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, scene_pipeline_layout_, 0, 1, &frame.scene_set, 0, nullptr);
    const std::int32_t no_eye = 0;
    vkCmdPushConstants(cmd, scene_pipeline_layout_, VK_SHADER_STAGE_VERTEX_BIT, 0, sizeof no_eye, &no_eye);
    set_viewport(shadow_.extent);
    draw_all(true);
    vkCmdEndRendering(cmd);
    transition(cmd, shadow_.image, VK_IMAGE_ASPECT_DEPTH_BIT, 1, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
               VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT, VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT,
               VK_ACCESS_2_SHADER_SAMPLED_READ_BIT);

    if (frame.timestamps) vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_ALL_GRAPHICS_BIT, frame.timestamps, 1);
    // 2. Both eyes, one pass.
    transition(cmd, eyes_.image, VK_IMAGE_ASPECT_COLOR_BIT, 2, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, none, 0,
               VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT);
    // Both depth layers cleared once, whether the eyes are drawn in one pass or two.
    transition(cmd, depth_.image, VK_IMAGE_ASPECT_DEPTH_BIT, 2, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
               VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT, 0, VK_PIPELINE_STAGE_2_CLEAR_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT);
    const VkClearDepthStencilValue far_depth{1.0f, 0};
    const VkImageSubresourceRange both_layers{VK_IMAGE_ASPECT_DEPTH_BIT, 0, 1, 0, 2};
    vkCmdClearDepthStencilImage(cmd, depth_.image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &far_depth, 1, &both_layers);
    transition(cmd, depth_.image, VK_IMAGE_ASPECT_DEPTH_BIT, 2, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL,
               VK_PIPELINE_STAGE_2_CLEAR_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
               VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT,
               VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT);
    VkRenderingAttachmentInfo colour{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
    colour.imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    colour.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
    colour.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    colour.clearValue.color = {{list.background.r, list.background.g, list.background.b, 1.0f}};
    VkRenderingAttachmentInfo depth = shadow_depth;
    depth.loadOp = VK_ATTACHMENT_LOAD_OP_LOAD;
    depth.storeOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
    VkRenderingInfo scene{VK_STRUCTURE_TYPE_RENDERING_INFO};
    scene.renderArea = {{0, 0}, eyes_.extent};
    scene.layerCount = 1;
    scene.colorAttachmentCount = 1;
    scene.pColorAttachments = &colour;
    scene.pDepthAttachment = &depth;
    // One multiview pass (viewMask 0b11: gl_ViewIndex picks the eye), or a pass per eye's layer.
    const int passes = multiview_ ? 1 : 2;
    for (int pass = 0; pass < passes; ++pass) {
        colour.imageView = multiview_ ? eyes_.view : eye_layer_[pass];
        depth.imageView = multiview_ ? depth_.view : depth_layer_[pass];
        scene.viewMask = multiview_ ? 0b11u : 0u;
        vkCmdBeginRendering(cmd, &scene);
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, multiview_ ? scene_pipeline_ : per_eye_pipeline_);
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, scene_pipeline_layout_, 0, 1, &frame.scene_set, 0, nullptr);
        const std::int32_t base = pass;
        vkCmdPushConstants(cmd, scene_pipeline_layout_, VK_SHADER_STAGE_VERTEX_BIT, 0, sizeof base, &base);
        set_viewport(eyes_.extent);
        draw_all(false);
        vkCmdEndRendering(cmd);
    }
    transition(cmd, eyes_.image, VK_IMAGE_ASPECT_COLOR_BIT, 2, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
               VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT,
               VK_ACCESS_2_SHADER_SAMPLED_READ_BIT);

    if (frame.timestamps) vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_ALL_GRAPHICS_BIT, frame.timestamps, 2);
    // 3. Composite to the display's format, into the offscreen output or the window's image. Side by
    // side and mono are plain copies of the eyes: a blit (on lavapipe far cheaper than a full-screen
    // fragment pass); interleaved rows and anaglyph need the composite shader.
    const bool blit = target.blit && (options_.mode == StereoMode::side_by_side || options_.mode == StereoMode::mono);
    VkImageLayout eyes_layout = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
    if (blit) {
        transition(cmd, eyes_.image, VK_IMAGE_ASPECT_COLOR_BIT, 2, eyes_layout, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                   VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT, VK_PIPELINE_STAGE_2_BLIT_BIT,
                   VK_ACCESS_2_TRANSFER_READ_BIT);
        eyes_layout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
        transition(cmd, target.image, VK_IMAGE_ASPECT_COLOR_BIT, 1, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                   VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, 0, VK_PIPELINE_STAGE_2_BLIT_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT);
        const auto w = static_cast<std::int32_t>(eyes_.extent.width), h = static_cast<std::int32_t>(eyes_.extent.height);
        VkImageBlit regions[2] = {};
        const std::uint32_t count = options_.mode == StereoMode::side_by_side ? 2u : 1u;
        for (std::uint32_t e = 0; e < count; ++e) {
            const auto x = static_cast<std::int32_t>(e) * w;
            regions[e].srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, e, 1};
            regions[e].srcOffsets[1] = {w, h, 1};
            regions[e].dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
            regions[e].dstOffsets[0] = {x, 0, 0};
            regions[e].dstOffsets[1] = {x + w, h, 1};
        }
        if (target.format == options_.colour_format) {
            // The same format: a plain copy (on lavapipe a memcpy, where a blit runs a shader).
            VkImageCopy copies[2] = {};
            for (std::uint32_t e = 0; e < count; ++e) {
                copies[e].srcSubresource = regions[e].srcSubresource;
                copies[e].dstSubresource = regions[e].dstSubresource;
                copies[e].dstOffset = regions[e].dstOffsets[0];
                copies[e].extent = {eyes_.extent.width, eyes_.extent.height, 1};
            }
            vkCmdCopyImage(cmd, eyes_.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, target.image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, count, copies);
        } else {
            vkCmdBlitImage(cmd, eyes_.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, target.image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, count, regions,
                           VK_FILTER_NEAREST);
        }
        transition(cmd, target.image, VK_IMAGE_ASPECT_COLOR_BIT, 1, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                   VK_PIPELINE_STAGE_2_BLIT_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
                   VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT);
    } else {
        transition(cmd, target.image, VK_IMAGE_ASPECT_COLOR_BIT, 1, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                   VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, 0, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
                   VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT);
    }
    VkRenderingAttachmentInfo out = colour;
    out.imageView = target.view;
    out.loadOp = blit ? VK_ATTACHMENT_LOAD_OP_LOAD : VK_ATTACHMENT_LOAD_OP_DONT_CARE;
    VkRenderingInfo composite{VK_STRUCTURE_TYPE_RENDERING_INFO};
    composite.renderArea = {{0, 0}, target.extent};
    composite.layerCount = 1;
    composite.colorAttachmentCount = 1;
    composite.pColorAttachments = &out;
    vkCmdBeginRendering(cmd, &composite);
    set_viewport(target.extent);
    if (!blit) {
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, target.pipeline);
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, composite_pipeline_layout_, 0, 1, &composite_set_, 0, nullptr);
        const CompositeConstants constants{static_cast<std::int32_t>(options_.mode), static_cast<std::int32_t>(options_.eye_width),
                                           static_cast<std::int32_t>(options_.eye_height), 0};
        vkCmdPushConstants(cmd, composite_pipeline_layout_, VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof constants, &constants);
        vkCmdDraw(cmd, 3, 1, 0, 0);
    }
    if (!frame.overlay_ranges.empty() && target.overlay_pipeline) {
        // Once per eye's area in side-by-side (at screen depth for both eyes), once otherwise.
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, target.overlay_pipeline);
        const VkDeviceSize zero = 0;
        vkCmdBindVertexBuffers(cmd, 0, 1, &frame.overlay.buffer, &zero);
        const int areas = options_.mode == StereoMode::side_by_side ? 2 : 1;
        for (int area = 0; area < areas; ++area) {
            for (std::size_t k = 0; k < overlay_.size() && k < frame.overlay_ranges.size(); ++k) {
                const auto [first, count] = frame.overlay_ranges[k];
                if (count == 0) continue;
                const OverlayConstants c{static_cast<float>(target.extent.width), static_cast<float>(target.extent.height),
                                         overlay_[k].origin_px.x + static_cast<float>(area) * static_cast<float>(options_.eye_width),
                                         overlay_[k].origin_px.y, overlay_[k].scale};
                vkCmdPushConstants(cmd, overlay_layout_, VK_SHADER_STAGE_VERTEX_BIT, 0, sizeof c, &c);
                vkCmdDraw(cmd, count, 1, first, 0);
            }
        }
    }
    vkCmdEndRendering(cmd);

    if (frame.timestamps) {
        vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_ALL_GRAPHICS_BIT, frame.timestamps, 3);
        frame.timestamps_written = true;
    }
    // 4. Read back (offscreen, or a screenshot of the window), then hand the window its image.
    VkImageLayout layout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    if (target.read_back) {
        transition(cmd, target.image, VK_IMAGE_ASPECT_COLOR_BIT, 1, layout, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                   VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT, VK_PIPELINE_STAGE_2_COPY_BIT,
                   VK_ACCESS_2_TRANSFER_READ_BIT);
        layout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
        VkBufferImageCopy region{};
        region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
        region.imageExtent = {target.extent.width, target.extent.height, 1};
        vkCmdCopyImageToBuffer(cmd, target.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, frame.readback.buffer, 1, &region);
    }
    if (target.present) {
        transition(cmd, target.image, VK_IMAGE_ASPECT_COLOR_BIT, 1, layout, VK_IMAGE_LAYOUT_PRESENT_SRC_KHR,
                   VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT | VK_PIPELINE_STAGE_2_COPY_BIT,
                   VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_2_TRANSFER_READ_BIT, VK_PIPELINE_STAGE_2_NONE, 0);
    }
    if (with_eyes) {
        if (eyes_layout != VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL) {
            transition(cmd, eyes_.image, VK_IMAGE_ASPECT_COLOR_BIT, 2, eyes_layout, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                       VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, VK_ACCESS_2_SHADER_SAMPLED_READ_BIT, VK_PIPELINE_STAGE_2_COPY_BIT,
                       VK_ACCESS_2_TRANSFER_READ_BIT);
        }
        VkBufferImageCopy eyes[2] = {};
        for (std::uint32_t e = 0; e < 2; ++e) {
            eyes[e].bufferOffset = 4ull * target.extent.width * target.extent.height + e * 4ull * eyes_.extent.width * eyes_.extent.height;
            eyes[e].imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, e, 1};
            eyes[e].imageExtent = {eyes_.extent.width, eyes_.extent.height, 1};
        }
        vkCmdCopyImageToBuffer(cmd, eyes_.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, frame.readback.buffer, 2, eyes);
    }
    VkMemoryBarrier2 host{VK_STRUCTURE_TYPE_MEMORY_BARRIER_2, nullptr, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                          VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT};
    VkDependencyInfo dep{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
    dep.memoryBarrierCount = 1;
    dep.pMemoryBarriers = &host;
    vkCmdPipelineBarrier2(cmd, &dep);
}

} // namespace ikebana::render
