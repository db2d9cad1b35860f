#pragma once
// The Vulkan 1.3 instance and device the renderer draws with: any GPU, or Mesa's lavapipe on machines
// without one (CI). Requires dynamic rendering and multiview (both eyes in one pass). Validation
// layers are enabled on request (debug builds, tests); every message they print is counted so a test
// can require zero errors. Failures are values (vk-bootstrap style), never exits.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "engine/core/result.hpp"

namespace ikebana::render {

struct ContextOptions {
    bool validation = false;
    bool require_validation = false; // fail when the layer is not installed
    std::vector<const char*> instance_extensions; // a window adds its surface extensions
};

class VulkanContext {
public:
    static Result<std::unique_ptr<VulkanContext>> create(const ContextOptions& options);
    ~VulkanContext();
    VulkanContext(const VulkanContext&) = delete;
    VulkanContext& operator=(const VulkanContext&) = delete;

    VkInstance instance() const noexcept { return instance_; }
    VkPhysicalDevice physical_device() const noexcept { return physical_; }
    VkDevice device() const noexcept { return device_; }
    VkQueue queue() const noexcept { return queue_; }
    std::uint32_t queue_family() const noexcept { return queue_family_; }
    const std::string& device_name() const noexcept { return device_name_; }
    bool validation_enabled() const noexcept { return messenger_ != VK_NULL_HANDLE; }
    std::uint32_t validation_errors() const noexcept { return counters_->errors; }
    std::uint32_t validation_warnings() const noexcept { return counters_->warnings; }

    struct ValidationCounters {
        std::uint32_t errors = 0;
        std::uint32_t warnings = 0;
    };

    // A memory type with these bits that also has `wanted` properties, or an error.
    Result<std::uint32_t> memory_type(std::uint32_t type_bits, VkMemoryPropertyFlags wanted) const;

private:
    VulkanContext() = default;
    VkInstance instance_ = VK_NULL_HANDLE;
    VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
    VkPhysicalDevice physical_ = VK_NULL_HANDLE;
    VkDevice device_ = VK_NULL_HANDLE;
    VkQueue queue_ = VK_NULL_HANDLE;
    std::uint32_t queue_family_ = 0;
    std::string device_name_;
    std::unique_ptr<ValidationCounters> counters_ = std::make_unique<ValidationCounters>();
};

// "vkCreateDevice failed: VK_ERROR_..." as an Error.
Error vulkan_error(const char* call, VkResult result);
const char* vk_result_name(VkResult result);

} // namespace ikebana::render
