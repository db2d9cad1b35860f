#pragma once
// Buffers, images and shader modules with their memory, created and destroyed as a unit. Buffers are
// host-visible and persistently mapped: on lavapipe all memory is, and the renderer's per-frame data
// (instances, uniforms) is written every frame anyway.
#include <cstdint>
#include <filesystem>

#include <vulkan/vulkan.h>

#include "engine/core/result.hpp"
#include "engine/render/vulkan_context.hpp"

namespace ikebana::render {

struct GpuBuffer {
    VkBuffer buffer = VK_NULL_HANDLE;
    VkDeviceMemory memory = VK_NULL_HANDLE;
    void* mapped = nullptr;
    VkDeviceSize size = 0;
};

struct GpuImage {
    VkImage image = VK_NULL_HANDLE;
    VkDeviceMemory memory = VK_NULL_HANDLE;
    VkImageView view = VK_NULL_HANDLE;
    VkFormat format = VK_FORMAT_UNDEFINED;
    VkExtent2D extent{0, 0};
    std::uint32_t layers = 1;
    std::uint32_t mip_levels = 1;
};

Result<GpuBuffer> create_buffer(const VulkanContext& ctx, VkDeviceSize size, VkBufferUsageFlags usage);
void destroy_buffer(const VulkanContext& ctx, GpuBuffer& buffer);

// A 2D image (array when layers > 1) with a view of all its layers and mip levels.
Result<GpuImage> create_image(const VulkanContext& ctx, VkFormat format, VkExtent2D extent, std::uint32_t layers, VkImageUsageFlags usage,
                              VkImageAspectFlags aspect, VkSampleCountFlagBits samples = VK_SAMPLE_COUNT_1_BIT, std::uint32_t mip_levels = 1);
void destroy_image(const VulkanContext& ctx, GpuImage& image);

// A SPIR-V file compiled at build time; the error names the file.
Result<VkShaderModule> load_shader(const VulkanContext& ctx, const std::filesystem::path& path);

// A layout transition for all layers of an image's first mip level (synchronization2); the second
// form for `count` mip levels from `first` of a single-layer colour image.
void transition(VkCommandBuffer cmd, VkImage image, VkImageAspectFlags aspect, std::uint32_t layers, VkImageLayout from, VkImageLayout to,
                VkPipelineStageFlags2 src_stage, VkAccessFlags2 src_access, VkPipelineStageFlags2 dst_stage, VkAccessFlags2 dst_access);
void transition_levels(VkCommandBuffer cmd, VkImage image, std::uint32_t first, std::uint32_t count, VkImageLayout from, VkImageLayout to,
                       VkPipelineStageFlags2 src_stage, VkAccessFlags2 src_access, VkPipelineStageFlags2 dst_stage, VkAccessFlags2 dst_access);

} // namespace ikebana::render
