#include "engine/platform/window.hpp"

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <thread>

#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>

#include "engine/render/vulkan_context.hpp"

namespace ikebana::platform {

Result<std::unique_ptr<Window>> Window::create(const std::string& title, std::uint32_t width, std::uint32_t height) {
    const char* display = std::getenv("DISPLAY");
    const char* wayland = std::getenv("WAYLAND_DISPLAY");
    if ((!display || !*display) && (!wayland || !*wayland)) return make_error(ErrorCode::device_error, "no display (DISPLAY is not set)");
    // An X server busy with another client's frames can refuse a connection for a moment (seen under
    // Xvfb on a loaded 2-core machine): a few tries, a quarter of a second apart, before giving up.
    bool started = false;
    std::string why_not;
    for (int attempt = 0; attempt < 4 && !started; ++attempt) {
        if (attempt > 0) std::this_thread::sleep_for(std::chrono::milliseconds(250));
        started = glfwInit() == GLFW_TRUE;
        if (!started) {
            const char* why = nullptr;
            glfwGetError(&why);
            why_not = why ? why : "unknown reason";
        }
    }
    if (!started) return make_error(ErrorCode::device_error, "GLFW cannot start: " + why_not);
    if (glfwVulkanSupported() != GLFW_TRUE) return make_error(ErrorCode::device_error, "GLFW finds no Vulkan loader for windows");
    glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
    glfwWindowHint(GLFW_RESIZABLE, GLFW_TRUE);
    std::unique_ptr<Window> w(new Window());
    for (int attempt = 0; attempt < 4 && !w->window_; ++attempt) {
        if (attempt > 0) std::this_thread::sleep_for(std::chrono::milliseconds(250));
        w->window_ = glfwCreateWindow(static_cast<int>(width), static_cast<int>(height), title.c_str(), nullptr, nullptr);
    }
    if (!w->window_) {
        const char* why = nullptr;
        glfwGetError(&why);
        return make_error(ErrorCode::device_error, std::string("cannot open a window: ") + (why ? why : "unknown reason"));
    }
    return w;
}

Window::~Window() {
    if (window_) glfwDestroyWindow(window_);
    glfwTerminate();
}

bool Window::should_close() const { return glfwWindowShouldClose(window_) == GLFW_TRUE; }
void Window::request_close() { glfwSetWindowShouldClose(window_, GLFW_TRUE); }
void Window::poll_events() { glfwPollEvents(); }
void Window::wait_events() { glfwWaitEventsTimeout(0.1); }

VkExtent2D Window::framebuffer() const {
    int w = 0, h = 0;
    glfwGetFramebufferSize(window_, &w, &h);
    return {static_cast<std::uint32_t>(std::max(w, 0)), static_cast<std::uint32_t>(std::max(h, 0))};
}

std::vector<const char*> Window::required_instance_extensions() {
    std::uint32_t count = 0;
    const char** names = glfwGetRequiredInstanceExtensions(&count);
    return names ? std::vector<const char*>(names, names + count) : std::vector<const char*>{};
}

Result<VkSurfaceKHR> Window::create_surface(VkInstance instance) const {
    VkSurfaceKHR surface = VK_NULL_HANDLE;
    if (VkResult r = glfwCreateWindowSurface(instance, window_, nullptr, &surface); r != VK_SUCCESS) return render::vulkan_error("glfwCreateWindowSurface", r);
    return surface;
}

bool Window::key_down(int key) const { return glfwGetKey(window_, key) == GLFW_PRESS; }
bool Window::mouse_down(int button) const { return glfwGetMouseButton(window_, button) == GLFW_PRESS; }
std::pair<double, double> Window::cursor() const {
    double x = 0.0, y = 0.0;
    glfwGetCursorPos(window_, &x, &y);
    return {x, y};
}

} // namespace ikebana::platform
