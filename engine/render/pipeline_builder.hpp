#pragma once
// Graphics pipelines for dynamic rendering, after the initializers of Sascha Willems' examples: the
// fixed-function state with defaults (triangle list, filled, no culling, one sample, dynamic viewport
// and scissor, no depth test, no attachments), changed by a few setters, then built once or more.
#include <cstdint>
#include <filesystem>
#include <initializer_list>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <vulkan/vulkan.h>

#include "engine/core/result.hpp"
#include "engine/render/vulkan_context.hpp"

namespace ikebana::render {

// A shader stage with its "main".
VkPipelineShaderStageCreateInfo shader_stage(VkShaderStageFlagBits stage, VkShaderModule module);
// Opaque: the colour replaces what is there, all four channels written.
VkPipelineColorBlendAttachmentState colour_write_all();
// "Over": colour by its alpha, alpha accumulated; all four channels written.
VkPipelineColorBlendAttachmentState alpha_blend();

class GraphicsPipelineBuilder {
public:
    explicit GraphicsPipelineBuilder(std::string pipeline_name) : name_(std::move(pipeline_name)) {}

    GraphicsPipelineBuilder& name(std::string pipeline_name); // in the error when building fails
    GraphicsPipelineBuilder& shaders(std::initializer_list<VkPipelineShaderStageCreateInfo> stages);
    GraphicsPipelineBuilder& vertex_input(std::span<const VkVertexInputBindingDescription> bindings,
                                          std::span<const VkVertexInputAttributeDescription> attributes);
    // Each colour attachment's format; each is blended with the one blend state.
    GraphicsPipelineBuilder& colour_formats(std::initializer_list<VkFormat> formats);
    GraphicsPipelineBuilder& blend(const VkPipelineColorBlendAttachmentState& attachment);
    GraphicsPipelineBuilder& depth_format(VkFormat format);
    GraphicsPipelineBuilder& depth_test(VkCompareOp compare, bool write);
    GraphicsPipelineBuilder& depth_bias(float constant_factor, float slope_factor);
    GraphicsPipelineBuilder& view_mask(std::uint32_t mask); // multiview: one bit per view
    GraphicsPipelineBuilder& dynamic_cull_mode();           // set with vkCmdSetCullMode per draw
    GraphicsPipelineBuilder& samples(VkSampleCountFlagBits count); // its targets' samples (multisampled: anti-aliased)

    // The error names the pipeline: "vkCreateGraphicsPipelines (scene) failed: ...".
    [[nodiscard]] Result<VkPipeline> build(VkDevice device, VkPipelineLayout layout) const;

private:
    std::string name_;
    std::vector<VkPipelineShaderStageCreateInfo> stages_;
    std::vector<VkVertexInputBindingDescription> bindings_;
    std::vector<VkVertexInputAttributeDescription> attributes_;
    std::vector<VkFormat> colour_formats_;
    VkPipelineColorBlendAttachmentState blend_ = colour_write_all();
    VkFormat depth_format_ = VK_FORMAT_UNDEFINED;
    VkCompareOp depth_compare_ = VK_COMPARE_OP_NEVER;
    bool depth_test_ = false, depth_write_ = false;
    bool depth_bias_ = false;
    float depth_bias_constant_ = 0.0f, depth_bias_slope_ = 0.0f;
    std::uint32_t view_mask_ = 0;
    bool dynamic_cull_mode_ = false;
    VkSampleCountFlagBits samples_ = VK_SAMPLE_COUNT_1_BIT;
};

// Shader modules loaded for one step and destroyed, in the order loaded, when it ends.
class ShaderModules {
public:
    ShaderModules(const VulkanContext& ctx, std::filesystem::path dir) : ctx_(ctx), dir_(std::move(dir)) {}
    ~ShaderModules();
    ShaderModules(const ShaderModules&) = delete;
    ShaderModules& operator=(const ShaderModules&) = delete;

    // The compiled SPIR-V `file` in the shader directory; the error names the file.
    Result<VkShaderModule> load(const std::string& file);

private:
    const VulkanContext& ctx_;
    std::filesystem::path dir_;
    std::vector<VkShaderModule> modules_;
};

} // namespace ikebana::render
