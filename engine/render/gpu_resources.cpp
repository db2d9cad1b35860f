#include "engine/render/gpu_resources.hpp"

#include <cstring>
#include <fstream>
#include <vector>

namespace ikebana::render {

Result<GpuBuffer> create_buffer(const VulkanContext& ctx, VkDeviceSize size, VkBufferUsageFlags usage) {
    GpuBuffer b;
    b.size = size;
    VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    info.size = size;
    info.usage = usage;
    info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    if (VkResult r = vkCreateBuffer(ctx.device(), &info, nullptr, &b.buffer); r != VK_SUCCESS) return vulkan_error("vkCreateBuffer", r);
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(ctx.device(), b.buffer, &req);
    auto type = ctx.memory_type(req.memoryTypeBits, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
    if (!type) {
        destroy_buffer(ctx, b);
        return std::move(type).error();
    }
    VkMemoryAllocateInfo alloc{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO, nullptr, req.size, *type};
    if (VkResult r = vkAllocateMemory(ctx.device(), &alloc, nullptr, &b.memory); r != VK_SUCCESS) {
        destroy_buffer(ctx, b);
        return vulkan_error("vkAllocateMemory", r);
    }
    vkBindBufferMemory(ctx.device(), b.buffer, b.memory, 0);
    if (VkResult r = vkMapMemory(ctx.device(), b.memory, 0, VK_WHOLE_SIZE, 0, &b.mapped); r != VK_SUCCESS) {
        destroy_buffer(ctx, b);
        return vulkan_error("vkMapMemory", r);
    }
    return b;
}

void destroy_buffer(const VulkanContext& ctx, GpuBuffer& b) {
    if (b.buffer) vkDestroyBuffer(ctx.device(), b.buffer, nullptr);
    if (b.memory) vkFreeMemory(ctx.device(), b.memory, nullptr);
    b = GpuBuffer{};
}

Result<GpuImage> create_image(const VulkanContext& ctx, VkFormat format, VkExtent2D extent, std::uint32_t layers, VkImageUsageFlags usage,
                              VkImageAspectFlags aspect, VkSampleCountFlagBits samples, std::uint32_t mip_levels) {
    GpuImage img;
    img.mip_levels = mip_levels;
    img.format = format;
    img.extent = extent;
    img.layers = layers;
    VkImageCreateInfo info{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
    info.imageType = VK_IMAGE_TYPE_2D;
    info.format = format;
    info.extent = {extent.width, extent.height, 1};
    info.mipLevels = mip_levels;
    info.arrayLayers = layers;
    info.samples = samples;
    info.tiling = VK_IMAGE_TILING_OPTIMAL;
    info.usage = usage;
    info.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    if (VkResult r = vkCreateImage(ctx.device(), &info, nullptr, &img.image); r != VK_SUCCESS) return vulkan_error("vkCreateImage", r);
    VkMemoryRequirements req;
    vkGetImageMemoryRequirements(ctx.device(), img.image, &req);
    auto type = ctx.memory_type(req.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    if (!type) type = ctx.memory_type(req.memoryTypeBits, 0);
    if (!type) {
        destroy_image(ctx, img);
        return std::move(type).error();
    }
    VkMemoryAllocateInfo alloc{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO, nullptr, req.size, *type};
    if (VkResult r = vkAllocateMemory(ctx.device(), &alloc, nullptr, &img.memory); r != VK_SUCCESS) {
        destroy_image(ctx, img);
        return vulkan_error("vkAllocateMemory", r);
    }
    vkBindImageMemory(ctx.device(), img.image, img.memory, 0);
    VkImageViewCreateInfo view{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
    view.image = img.image;
    view.viewType = layers > 1 ? VK_IMAGE_VIEW_TYPE_2D_ARRAY : VK_IMAGE_VIEW_TYPE_2D;
    view.format = format;
    view.subresourceRange = {aspect, 0, mip_levels, 0, layers};
    if (VkResult r = vkCreateImageView(ctx.device(), &view, nullptr, &img.view); r != VK_SUCCESS) {
        destroy_image(ctx, img);
        return vulkan_error("vkCreateImageView", r);
    }
    return img;
}

void destroy_image(const VulkanContext& ctx, GpuImage& img) {
    if (img.view) vkDestroyImageView(ctx.device(), img.view, nullptr);
    if (img.image) vkDestroyImage(ctx.device(), img.image, nullptr);
    if (img.memory) vkFreeMemory(ctx.device(), img.memory, nullptr);
    img = GpuImage{};
}

Result<VkShaderModule> load_shader(const VulkanContext& ctx, const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return make_error(ErrorCode::not_found, path.string() + ": no such shader (built from shaders/ by glslang)");
    std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (bytes.empty() || bytes.size() % 4 != 0) return make_error(ErrorCode::parse_error, path.string() + ": not SPIR-V");
    std::vector<std::uint32_t> words(bytes.size() / 4);
    std::memcpy(words.data(), bytes.data(), bytes.size());
    if (words[0] != 0x07230203u) return make_error(ErrorCode::parse_error, path.string() + ": not SPIR-V (bad magic number)");
    VkShaderModuleCreateInfo info{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO, nullptr, 0, bytes.size(), words.data()};
    VkShaderModule module = VK_NULL_HANDLE;
    if (VkResult r = vkCreateShaderModule(ctx.device(), &info, nullptr, &module); r != VK_SUCCESS) return vulkan_error("vkCreateShaderModule", r);
    return module;
}

namespace {

void barrier(VkCommandBuffer cmd, VkImage image, VkImageSubresourceRange range, VkImageLayout from, VkImageLayout to, VkPipelineStageFlags2 src_stage,
             VkAccessFlags2 src_access, VkPipelineStageFlags2 dst_stage, VkAccessFlags2 dst_access) {
    VkImageMemoryBarrier2 b{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER_2};
    b.srcStageMask = src_stage;
    b.srcAccessMask = src_access;
    b.dstStageMask = dst_stage;
    b.dstAccessMask = dst_access;
    b.oldLayout = from;
    b.newLayout = to;
    b.srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    b.image = image;
    b.subresourceRange = range;
    VkDependencyInfo dep{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
    dep.imageMemoryBarrierCount = 1;
    dep.pImageMemoryBarriers = &b;
    vkCmdPipelineBarrier2(cmd, &dep);
}

} // namespace

void transition(VkCommandBuffer cmd, VkImage image, VkImageAspectFlags aspect, std::uint32_t layers, VkImageLayout from, VkImageLayout to,
                VkPipelineStageFlags2 src_stage, VkAccessFlags2 src_access, VkPipelineStageFlags2 dst_stage, VkAccessFlags2 dst_access) {
    barrier(cmd, image, {aspect, 0, 1, 0, layers}, from, to, src_stage, src_access, dst_stage, dst_access);
}

void transition_levels(VkCommandBuffer cmd, VkImage image, std::uint32_t first, std::uint32_t count, VkImageLayout from, VkImageLayout to,
                       VkPipelineStageFlags2 src_stage, VkAccessFlags2 src_access, VkPipelineStageFlags2 dst_stage, VkAccessFlags2 dst_access) {
    barrier(cmd, image, {VK_IMAGE_ASPECT_COLOR_BIT, first, count, 0, 1}, from, to, src_stage, src_access, dst_stage, dst_access);
}

} // namespace ikebana::render
