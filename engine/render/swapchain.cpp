#include "engine/render/swapchain.hpp"

#include <algorithm>

namespace ikebana::render {

Result<std::unique_ptr<Swapchain>> Swapchain::create(VulkanContext& ctx, VkSurfaceKHR surface, VkExtent2D wanted) {
    VkBool32 supported = VK_FALSE;
    vkGetPhysicalDeviceSurfaceSupportKHR(ctx.physical_device(), ctx.queue_family(), surface, &supported);
    if (!supported) return make_error(ErrorCode::device_error, ctx.device_name() + " cannot present to this window");
    std::unique_ptr<Swapchain> s(new Swapchain(ctx, surface));
    if (auto r = s->build(wanted); !r) return std::move(r).error();
    return s;
}

Swapchain::~Swapchain() {
    vkDeviceWaitIdle(ctx_.device());
    destroy_views();
    if (swapchain_) vkDestroySwapchainKHR(ctx_.device(), swapchain_, nullptr);
}

void Swapchain::destroy_views() {
    for (VkImageView v : views_) vkDestroyImageView(ctx_.device(), v, nullptr);
    views_.clear();
}

Result<void> Swapchain::build(VkExtent2D wanted) {
    VkSurfaceCapabilitiesKHR caps;
    if (VkResult r = vkGetPhysicalDeviceSurfaceCapabilitiesKHR(ctx_.physical_device(), surface_, &caps); r != VK_SUCCESS) {
        return vulkan_error("vkGetPhysicalDeviceSurfaceCapabilitiesKHR", r);
    }
    std::uint32_t count = 0;
    vkGetPhysicalDeviceSurfaceFormatsKHR(ctx_.physical_device(), surface_, &count, nullptr);
    std::vector<VkSurfaceFormatKHR> formats(count);
    vkGetPhysicalDeviceSurfaceFormatsKHR(ctx_.physical_device(), surface_, &count, formats.data());
    if (formats.empty()) return make_error(ErrorCode::device_error, "the window offers no image formats");
    // UNORM like the offscreen images, so the window shows what `ikebana render` writes.
    VkSurfaceFormatKHR chosen = formats[0];
    for (const auto& f : formats) {
        if (f.format == VK_FORMAT_B8G8R8A8_UNORM || f.format == VK_FORMAT_R8G8B8A8_UNORM) {
            chosen = f;
            break;
        }
    }
    VkExtent2D extent = caps.currentExtent.width != UINT32_MAX ? caps.currentExtent : wanted;
    extent.width = std::clamp(extent.width, caps.minImageExtent.width, caps.maxImageExtent.width);
    extent.height = std::clamp(extent.height, caps.minImageExtent.height, caps.maxImageExtent.height);
    if (extent.width == 0 || extent.height == 0) return make_error(ErrorCode::invalid_argument, "the window has no area (minimised)");
    std::uint32_t images = std::max(caps.minImageCount + 1, 2u);
    if (caps.maxImageCount > 0) images = std::min(images, caps.maxImageCount);
    transfer_src_ = (caps.supportedUsageFlags & VK_IMAGE_USAGE_TRANSFER_SRC_BIT) != 0;
    transfer_dst_ = (caps.supportedUsageFlags & VK_IMAGE_USAGE_TRANSFER_DST_BIT) != 0;
    VkSwapchainCreateInfoKHR info{VK_STRUCTURE_TYPE_SWAPCHAIN_CREATE_INFO_KHR};
    info.surface = surface_;
    info.minImageCount = images;
    info.imageFormat = chosen.format;
    info.imageColorSpace = chosen.colorSpace;
    info.imageExtent = extent;
    info.imageArrayLayers = 1;
    info.imageUsage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT;
    if (transfer_src_) info.imageUsage |= VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
    if (transfer_dst_) info.imageUsage |= VK_IMAGE_USAGE_TRANSFER_DST_BIT;
    info.imageSharingMode = VK_SHARING_MODE_EXCLUSIVE;
    info.preTransform = caps.currentTransform;
    info.compositeAlpha = VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR;
    info.presentMode = VK_PRESENT_MODE_FIFO_KHR; // always available; paces the loop to the display
    info.clipped = VK_TRUE;
    info.oldSwapchain = swapchain_;
    VkSwapchainKHR fresh = VK_NULL_HANDLE;
    if (VkResult r = vkCreateSwapchainKHR(ctx_.device(), &info, nullptr, &fresh); r != VK_SUCCESS) return vulkan_error("vkCreateSwapchainKHR", r);
    destroy_views();
    if (swapchain_) vkDestroySwapchainKHR(ctx_.device(), swapchain_, nullptr);
    swapchain_ = fresh;
    format_ = chosen.format;
    extent_ = extent;
    vkGetSwapchainImagesKHR(ctx_.device(), swapchain_, &count, nullptr);
    images_.resize(count);
    vkGetSwapchainImagesKHR(ctx_.device(), swapchain_, &count, images_.data());
    for (VkImage image : images_) {
        VkImageViewCreateInfo view{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
        view.image = image;
        view.viewType = VK_IMAGE_VIEW_TYPE_2D;
        view.format = format_;
        view.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
        VkImageView v = VK_NULL_HANDLE;
        if (VkResult r = vkCreateImageView(ctx_.device(), &view, nullptr, &v); r != VK_SUCCESS) return vulkan_error("vkCreateImageView", r);
        views_.push_back(v);
    }
    return Ok{};
}

Result<void> Swapchain::recreate(VkExtent2D wanted) {
    vkDeviceWaitIdle(ctx_.device());
    return build(wanted);
}

Result<std::optional<std::uint32_t>> Swapchain::acquire(VkSemaphore signal) {
    std::uint32_t index = 0;
    const VkResult r = vkAcquireNextImageKHR(ctx_.device(), swapchain_, UINT64_MAX, signal, VK_NULL_HANDLE, &index);
    if (r == VK_ERROR_OUT_OF_DATE_KHR) return std::optional<std::uint32_t>{};
    if (r != VK_SUCCESS && r != VK_SUBOPTIMAL_KHR) return vulkan_error("vkAcquireNextImageKHR", r);
    return std::optional<std::uint32_t>{index};
}

Result<bool> Swapchain::present(std::uint32_t image, VkSemaphore wait) {
    VkPresentInfoKHR info{VK_STRUCTURE_TYPE_PRESENT_INFO_KHR};
    info.waitSemaphoreCount = 1;
    info.pWaitSemaphores = &wait;
    info.swapchainCount = 1;
    info.pSwapchains = &swapchain_;
    info.pImageIndices = &image;
    const VkResult r = vkQueuePresentKHR(ctx_.queue(), &info);
    if (r == VK_ERROR_OUT_OF_DATE_KHR || r == VK_SUBOPTIMAL_KHR) return false;
    if (r != VK_SUCCESS) return vulkan_error("vkQueuePresentKHR", r);
    return true;
}

} // namespace ikebana::render
