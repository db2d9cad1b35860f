#include "engine/render/pipeline_builder.hpp"

#include "engine/render/gpu_resources.hpp"

namespace ikebana::render {

namespace {

template <class T> std::uint32_t count(const std::vector<T>& v) { return static_cast<std::uint32_t>(v.size()); }
template <class T> const T* data_or_null(const std::vector<T>& v) { return v.empty() ? nullptr : v.data(); }

VkPipelineRasterizationStateCreateInfo rasterization(bool bias, float bias_constant, float bias_slope) {
    VkPipelineRasterizationStateCreateInfo raster{VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO};
    raster.polygonMode = VK_POLYGON_MODE_FILL;
    raster.cullMode = VK_CULL_MODE_NONE;
    raster.frontFace = VK_FRONT_FACE_COUNTER_CLOCKWISE;
    raster.depthBiasEnable = bias ? VK_TRUE : VK_FALSE;
    raster.depthBiasConstantFactor = bias_constant;
    raster.depthBiasSlopeFactor = bias_slope;
    raster.lineWidth = 1.0f;
    return raster;
}

VkPipelineDepthStencilStateCreateInfo depth_stencil(bool test, bool write, VkCompareOp compare) {
    VkPipelineDepthStencilStateCreateInfo depth{VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO};
    depth.depthTestEnable = test ? VK_TRUE : VK_FALSE;
    depth.depthWriteEnable = write ? VK_TRUE : VK_FALSE;
    depth.depthCompareOp = compare;
    return depth;
}

} // namespace

VkPipelineShaderStageCreateInfo shader_stage(VkShaderStageFlagBits stage, VkShaderModule module) {
    return {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO, nullptr, 0, stage, module, "main", nullptr};
}

VkPipelineColorBlendAttachmentState colour_write_all() {
    VkPipelineColorBlendAttachmentState opaque{};
    opaque.colorWriteMask = VK_COLOR_COMPONENT_R_BIT | VK_COLOR_COMPONENT_G_BIT | VK_COLOR_COMPONENT_B_BIT | VK_COLOR_COMPONENT_A_BIT;
    return opaque;
}

VkPipelineColorBlendAttachmentState alpha_blend() {
    VkPipelineColorBlendAttachmentState alpha = colour_write_all();
    alpha.blendEnable = VK_TRUE;
    alpha.srcColorBlendFactor = VK_BLEND_FACTOR_SRC_ALPHA;
    alpha.dstColorBlendFactor = VK_BLEND_FACTOR_ONE_MINUS_SRC_ALPHA;
    alpha.colorBlendOp = VK_BLEND_OP_ADD;
    alpha.srcAlphaBlendFactor = VK_BLEND_FACTOR_ONE;
    alpha.dstAlphaBlendFactor = VK_BLEND_FACTOR_ONE_MINUS_SRC_ALPHA;
    alpha.alphaBlendOp = VK_BLEND_OP_ADD;
    return alpha;
}

GraphicsPipelineBuilder& GraphicsPipelineBuilder::name(std::string pipeline_name) {
    name_ = std::move(pipeline_name);
    return *this;
}

GraphicsPipelineBuilder& GraphicsPipelineBuilder::shaders(std::initializer_list<VkPipelineShaderStageCreateInfo> stages) {
    stages_.assign(stages);
    return *this;
}

GraphicsPipelineBuilder& GraphicsPipelineBuilder::vertex_input(std::span<const VkVertexInputBindingDescription> bindings,
                                                               std::span<const VkVertexInputAttributeDescription> attributes) {
    bindings_.assign(bindings.begin(), bindings.end());
    attributes_.assign(attributes.begin(), attributes.end());
    return *this;
}

GraphicsPipelineBuilder& GraphicsPipelineBuilder::colour_formats(std::initializer_list<VkFormat> formats) {
    colour_formats_.assign(formats);
    return *this;
}

GraphicsPipelineBuilder& GraphicsPipelineBuilder::blend(const VkPipelineColorBlendAttachmentState& attachment) {
    blend_ = attachment;
    return *this;
}

GraphicsPipelineBuilder& GraphicsPipelineBuilder::depth_format(VkFormat format) {
    depth_format_ = format;
    return *this;
}

GraphicsPipelineBuilder& GraphicsPipelineBuilder::depth_test(VkCompareOp compare, bool write) {
    depth_test_ = true;
    depth_write_ = write;
    depth_compare_ = compare;
    return *this;
}

GraphicsPipelineBuilder& GraphicsPipelineBuilder::depth_bias(float constant_factor, float slope_factor) {
    depth_bias_ = true;
    depth_bias_constant_ = constant_factor;
    depth_bias_slope_ = slope_factor;
    return *this;
}

GraphicsPipelineBuilder& GraphicsPipelineBuilder::view_mask(std::uint32_t mask) {
    view_mask_ = mask;
    return *this;
}

GraphicsPipelineBuilder& GraphicsPipelineBuilder::dynamic_cull_mode() {
    dynamic_cull_mode_ = true;
    return *this;
}

GraphicsPipelineBuilder& GraphicsPipelineBuilder::samples(VkSampleCountFlagBits count) {
    samples_ = count;
    return *this;
}

Result<VkPipeline> GraphicsPipelineBuilder::build(VkDevice device, VkPipelineLayout layout) const {
    VkPipelineRenderingCreateInfo rendering{VK_STRUCTURE_TYPE_PIPELINE_RENDERING_CREATE_INFO};
    rendering.viewMask = view_mask_;
    rendering.colorAttachmentCount = count(colour_formats_);
    rendering.pColorAttachmentFormats = data_or_null(colour_formats_);
    rendering.depthAttachmentFormat = depth_format_;
    const VkPipelineVertexInputStateCreateInfo input{VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO, nullptr, 0, count(bindings_),
                                                     data_or_null(bindings_), count(attributes_), data_or_null(attributes_)};
    const VkPipelineInputAssemblyStateCreateInfo assembly{VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO, nullptr, 0,
                                                          VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST, VK_FALSE};
    const VkPipelineViewportStateCreateInfo viewport{VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO, nullptr, 0, 1, nullptr, 1, nullptr};
    const auto raster = rasterization(depth_bias_, depth_bias_constant_, depth_bias_slope_);
    VkPipelineMultisampleStateCreateInfo multisample{VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO};
    multisample.rasterizationSamples = samples_;
    const auto depth = depth_stencil(depth_test_, depth_write_, depth_compare_);
    const std::vector<VkPipelineColorBlendAttachmentState> blends(colour_formats_.size(), blend_);
    VkPipelineColorBlendStateCreateInfo blend{VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO};
    blend.attachmentCount = count(blends);
    blend.pAttachments = data_or_null(blends);
    std::vector<VkDynamicState> dynamic_states{VK_DYNAMIC_STATE_VIEWPORT, VK_DYNAMIC_STATE_SCISSOR};
    if (dynamic_cull_mode_) dynamic_states.push_back(VK_DYNAMIC_STATE_CULL_MODE);
    const VkPipelineDynamicStateCreateInfo dynamic{VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO, nullptr, 0, count(dynamic_states),
                                                   dynamic_states.data()};
    VkGraphicsPipelineCreateInfo info{VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO};
    info.pNext = &rendering;
    info.stageCount = count(stages_);
    info.pStages = data_or_null(stages_);
    info.pVertexInputState = &input;
    info.pInputAssemblyState = &assembly;
    info.pViewportState = &viewport;
    info.pRasterizationState = &raster;
    info.pMultisampleState = &multisample;
    info.pDepthStencilState = &depth;
    info.pColorBlendState = &blend;
    info.pDynamicState = &dynamic;
    info.layout = layout;
    VkPipeline pipeline = VK_NULL_HANDLE;
    if (const VkResult r = vkCreateGraphicsPipelines(device, VK_NULL_HANDLE, 1, &info, nullptr, &pipeline); r != VK_SUCCESS) {
        return vulkan_error(("vkCreateGraphicsPipelines (" + name_ + ")").c_str(), r);
    }
    return pipeline;
}

ShaderModules::~ShaderModules() {
    for (VkShaderModule m : modules_) vkDestroyShaderModule(ctx_.device(), m, nullptr);
}

Result<VkShaderModule> ShaderModules::load(const std::string& file) {
    auto module = load_shader(ctx_, dir_ / file);
    if (!module) return std::move(module).error();
    modules_.push_back(*module);
    return *module;
}

} // namespace ikebana::render
