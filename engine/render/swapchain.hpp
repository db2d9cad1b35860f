#pragma once
// The window's images. Out of date or suboptimal (a resize) and a zero-size framebuffer (minimised)
// are reported, not fatal: the caller recreates with the new size, or waits.
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include <vulkan/vulkan.h>

#include "engine/core/result.hpp"
#include "engine/render/vulkan_context.hpp"

namespace ikebana::render {

class Swapchain {
public:
    static Result<std::unique_ptr<Swapchain>> create(VulkanContext& ctx, VkSurfaceKHR surface, VkExtent2D wanted);
    ~Swapchain();
    Swapchain(const Swapchain&) = delete;
    Swapchain& operator=(const Swapchain&) = delete;

    // Rebuilds for a new framebuffer size (the old images are retired after the device is idle).
    Result<void> recreate(VkExtent2D wanted);
    // The next image, or nothing when the swapchain is out of date (recreate, then try again).
    Result<std::optional<std::uint32_t>> acquire(VkSemaphore signal);
    // false when out of date or suboptimal: recreate before the next frame.
    Result<bool> present(std::uint32_t image, VkSemaphore wait);

    [[nodiscard]] VkFormat format() const noexcept { return format_; }
    [[nodiscard]] VkExtent2D extent() const noexcept { return extent_; }
    [[nodiscard]] VkImage image(std::uint32_t i) const { return images_[i]; }
    [[nodiscard]] VkImageView view(std::uint32_t i) const { return views_[i]; }
    [[nodiscard]] std::uint32_t image_count() const noexcept { return static_cast<std::uint32_t>(images_.size()); }
    [[nodiscard]] bool can_copy_from() const noexcept { return transfer_src_; }
    [[nodiscard]] bool can_copy_to() const noexcept { return transfer_dst_; }

private:
    Swapchain(VulkanContext& ctx, VkSurfaceKHR surface) : ctx_(ctx), surface_(surface) {}
    Result<void> build(VkExtent2D wanted);
    void destroy_views();

    VulkanContext& ctx_;
    VkSurfaceKHR surface_;
    VkSwapchainKHR swapchain_ = VK_NULL_HANDLE;
    VkFormat format_ = VK_FORMAT_UNDEFINED;
    VkExtent2D extent_{0, 0};
    std::vector<VkImage> images_;
    std::vector<VkImageView> views_;
    bool transfer_src_ = false;
    bool transfer_dst_ = false;
};

} // namespace ikebana::render
