#pragma once
// The trainee's window: GLFW with no client API (Vulkan draws into it). No display, or a GLFW that
// cannot start, is an error the caller can act on (the app renders offscreen instead).
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "engine/core/result.hpp"

struct GLFWwindow;

namespace ikebana::platform {

class Window {
public:
    static Result<std::unique_ptr<Window>> create(const std::string& title, std::uint32_t width, std::uint32_t height);
    ~Window();
    Window(const Window&) = delete;
    Window& operator=(const Window&) = delete;

    [[nodiscard]] GLFWwindow* glfw() const noexcept { return window_; }
    [[nodiscard]] bool should_close() const;
    void request_close();
    void poll_events();
    void wait_events(); // while minimised: sleep until something happens
    // The framebuffer in pixels (0 x 0 while minimised).
    [[nodiscard]] VkExtent2D framebuffer() const;
    [[nodiscard]] static std::vector<const char*> required_instance_extensions();
    Result<VkSurfaceKHR> create_surface(VkInstance instance) const;
    [[nodiscard]] bool key_down(int glfw_key) const;
    [[nodiscard]] bool mouse_down(int glfw_button) const;
    [[nodiscard]] std::pair<double, double> cursor() const;

private:
    Window() = default;
    GLFWwindow* window_ = nullptr;
};

} // namespace ikebana::platform
