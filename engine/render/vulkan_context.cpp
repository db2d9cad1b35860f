#include "engine/render/vulkan_context.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <thread>
#include <cstring>

namespace ikebana::render {

const char* vk_result_name(VkResult r) {
    switch (r) {
    case VK_SUCCESS: return "VK_SUCCESS";
    case VK_ERROR_OUT_OF_HOST_MEMORY: return "VK_ERROR_OUT_OF_HOST_MEMORY";
    case VK_ERROR_OUT_OF_DEVICE_MEMORY: return "VK_ERROR_OUT_OF_DEVICE_MEMORY";
    case VK_ERROR_INITIALIZATION_FAILED: return "VK_ERROR_INITIALIZATION_FAILED";
    case VK_ERROR_DEVICE_LOST: return "VK_ERROR_DEVICE_LOST";
    case VK_ERROR_LAYER_NOT_PRESENT: return "VK_ERROR_LAYER_NOT_PRESENT";
    case VK_ERROR_EXTENSION_NOT_PRESENT: return "VK_ERROR_EXTENSION_NOT_PRESENT";
    case VK_ERROR_FEATURE_NOT_PRESENT: return "VK_ERROR_FEATURE_NOT_PRESENT";
    case VK_ERROR_INCOMPATIBLE_DRIVER: return "VK_ERROR_INCOMPATIBLE_DRIVER";
    case VK_ERROR_OUT_OF_DATE_KHR: return "VK_ERROR_OUT_OF_DATE_KHR";
    case VK_SUBOPTIMAL_KHR: return "VK_SUBOPTIMAL_KHR";
    case VK_TIMEOUT: return "VK_TIMEOUT";
    default: return "VkResult";
    }
}

Error vulkan_error(const char* call, VkResult result) {
    return make_error(ErrorCode::device_error, std::string(call) + " failed: " + vk_result_name(result) + " (" + std::to_string(result) + ")");
}

namespace {

VKAPI_ATTR VkBool32 VKAPI_CALL on_validation_message(VkDebugUtilsMessageSeverityFlagBitsEXT severity, VkDebugUtilsMessageTypeFlagsEXT,
                                                     const VkDebugUtilsMessengerCallbackDataEXT* data, void* user) {
    auto* counters = static_cast<VulkanContext::ValidationCounters*>(user);
    if (severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT) {
        ++counters->errors;
        std::fprintf(stderr, "vulkan validation error: %s\n", data->pMessage);
    } else if (severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT) {
        ++counters->warnings;
        std::fprintf(stderr, "vulkan validation warning: %s\n", data->pMessage);
    }
    return VK_FALSE;
}

bool layer_available(const char* name) {
    std::uint32_t count = 0;
    vkEnumerateInstanceLayerProperties(&count, nullptr);
    std::vector<VkLayerProperties> layers(count);
    vkEnumerateInstanceLayerProperties(&count, layers.data());
    for (const auto& l : layers) {
        if (std::strcmp(l.layerName, name) == 0) return true;
    }
    return false;
}

int device_rank(VkPhysicalDeviceType type) {
    switch (type) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return 4;
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return 3;
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return 2;
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return 1;
    default: return 0;
    }
}

} // namespace

Result<std::unique_ptr<VulkanContext>> VulkanContext::create(const ContextOptions& options) {
    // lavapipe (llvmpipe) shades vertices and bins triangles on its queue thread and rasterises on as
    // many threads as there are cores, so a core idles while geometry runs. One rasteriser thread more
    // than the cores keeps both busy: on this 2-core machine a frame of the default scene goes from
    // about 29 to 23 ms. Read by Mesa when the device is created; a value the user set is kept, and
    // GPUs ignore it.
    if (!std::getenv("LP_NUM_THREADS")) {
        const std::string threads = std::to_string(std::max(1u, std::thread::hardware_concurrency()) + 1);
        setenv("LP_NUM_THREADS", threads.c_str(), 0);
    }
    std::unique_ptr<VulkanContext> ctx(new VulkanContext());
    const char* validation_layer = "VK_LAYER_KHRONOS_validation";
    const bool validation = options.validation && layer_available(validation_layer);
    if (options.validation && !validation && options.require_validation) {
        return make_error(ErrorCode::device_error, "the Vulkan validation layer is not installed (Debian: vulkan-validationlayers)");
    }
    VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO, nullptr, "ikebana", 1, "ikebana", 1, VK_API_VERSION_1_3};
    std::vector<const char*> extensions = options.instance_extensions;
    if (validation) extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
    VkInstanceCreateInfo info{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
    info.pApplicationInfo = &app;
    info.enabledLayerCount = validation ? 1u : 0u;
    info.ppEnabledLayerNames = validation ? &validation_layer : nullptr;
    info.enabledExtensionCount = static_cast<std::uint32_t>(extensions.size());
    info.ppEnabledExtensionNames = extensions.data();
    if (VkResult r = vkCreateInstance(&info, nullptr, &ctx->instance_); r != VK_SUCCESS) {
        if (r == VK_ERROR_INCOMPATIBLE_DRIVER) {
            return make_error(ErrorCode::device_error, "no Vulkan driver is installed (Debian: mesa-vulkan-drivers gives lavapipe)");
        }
        return vulkan_error("vkCreateInstance", r);
    }
    if (validation) {
        auto create_messenger = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(vkGetInstanceProcAddr(ctx->instance_, "vkCreateDebugUtilsMessengerEXT"));
        VkDebugUtilsMessengerCreateInfoEXT m{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
        m.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
        m.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                        VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
        m.pfnUserCallback = on_validation_message;
        m.pUserData = ctx->counters_.get(); // on the heap: stays put for the messenger's life
        if (create_messenger) create_messenger(ctx->instance_, &m, nullptr, &ctx->messenger_);
    }
    std::uint32_t count = 0;
    vkEnumeratePhysicalDevices(ctx->instance_, &count, nullptr);
    std::vector<VkPhysicalDevice> devices(count);
    vkEnumeratePhysicalDevices(ctx->instance_, &count, devices.data());
    int best_rank = -1;
    std::string refused;
    for (VkPhysicalDevice d : devices) {
        VkPhysicalDeviceProperties props;
        vkGetPhysicalDeviceProperties(d, &props);
        VkPhysicalDeviceVulkan11Features v11{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_1_FEATURES};
        VkPhysicalDeviceVulkan13Features v13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES};
        v11.pNext = &v13;
        VkPhysicalDeviceFeatures2 features{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, &v11, {}};
        vkGetPhysicalDeviceFeatures2(d, &features);
        const bool ok = props.apiVersion >= VK_API_VERSION_1_3 && v11.multiview && v13.dynamicRendering && v13.synchronization2;
        if (!ok) {
            refused += std::string(refused.empty() ? "" : ", ") + props.deviceName;
            continue;
        }
        std::uint32_t families = 0;
        vkGetPhysicalDeviceQueueFamilyProperties(d, &families, nullptr);
        std::vector<VkQueueFamilyProperties> family(families);
        vkGetPhysicalDeviceQueueFamilyProperties(d, &families, family.data());
        for (std::uint32_t q = 0; q < families; ++q) {
            if ((family[q].queueFlags & VK_QUEUE_GRAPHICS_BIT) && device_rank(props.deviceType) > best_rank) {
                best_rank = device_rank(props.deviceType);
                ctx->physical_ = d;
                ctx->queue_family_ = q;
                ctx->device_name_ = props.deviceName;
                break;
            }
        }
    }
    if (ctx->physical_ == VK_NULL_HANDLE) {
        return make_error(ErrorCode::device_error, count == 0 ? std::string("no Vulkan device found (Debian: mesa-vulkan-drivers gives lavapipe)")
                                                              : "no Vulkan 1.3 device with multiview and dynamic rendering (found: " + refused + ")");
    }
    const float priority = 1.0f;
    VkDeviceQueueCreateInfo queue{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO, nullptr, 0, ctx->queue_family_, 1, &priority};
    VkPhysicalDeviceVulkan13Features v13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES};
    v13.dynamicRendering = VK_TRUE;
    v13.synchronization2 = VK_TRUE;
    VkPhysicalDeviceVulkan11Features v11{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_1_FEATURES};
    v11.multiview = VK_TRUE;
    v11.pNext = &v13;
    std::vector<const char*> device_extensions;
    if (!options.instance_extensions.empty()) device_extensions.push_back(VK_KHR_SWAPCHAIN_EXTENSION_NAME);
    VkDeviceCreateInfo dinfo{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
    dinfo.pNext = &v11;
    dinfo.queueCreateInfoCount = 1;
    dinfo.pQueueCreateInfos = &queue;
    dinfo.enabledExtensionCount = static_cast<std::uint32_t>(device_extensions.size());
    dinfo.ppEnabledExtensionNames = device_extensions.data();
    if (VkResult r = vkCreateDevice(ctx->physical_, &dinfo, nullptr, &ctx->device_); r != VK_SUCCESS) return vulkan_error("vkCreateDevice", r);
    vkGetDeviceQueue(ctx->device_, ctx->queue_family_, 0, &ctx->queue_);
    return ctx;
}

VulkanContext::~VulkanContext() {
    if (device_) vkDestroyDevice(device_, nullptr);
    if (messenger_) {
        auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(vkGetInstanceProcAddr(instance_, "vkDestroyDebugUtilsMessengerEXT"));
        if (destroy) destroy(instance_, messenger_, nullptr);
    }
    if (instance_) vkDestroyInstance(instance_, nullptr);
}

Result<std::uint32_t> VulkanContext::memory_type(std::uint32_t type_bits, VkMemoryPropertyFlags wanted) const {
    VkPhysicalDeviceMemoryProperties props;
    vkGetPhysicalDeviceMemoryProperties(physical_, &props);
    for (std::uint32_t i = 0; i < props.memoryTypeCount; ++i) {
        if ((type_bits & (1u << i)) && (props.memoryTypes[i].propertyFlags & wanted) == wanted) return i;
    }
    return make_error(ErrorCode::device_error, "no Vulkan memory type with the wanted properties");
}

} // namespace ikebana::render
