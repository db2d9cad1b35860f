#pragma once
// What every window of the app stands on: the window, Vulkan on it (context, surface, swapchain),
// the stereo renderer, the window's pointer and the interface layer (Dear ImGui). The trainee's
// session and the replay both draw through it: one path from a draw list to the screen, which keeps
// the swapchain fitted to the window's size. Members go in reverse order: the interface and the
// renderer before the swapchain, the surface before the context, the context before the window.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include <vulkan/vulkan.h>

#include "engine/core/result.hpp"
#include "engine/platform/pointer_input.hpp"
#include "engine/platform/window.hpp"
#include "engine/render/stereo_renderer.hpp"
#include "engine/render/swapchain.hpp"
#include "engine/render/ui_layer.hpp"
#include "engine/render/vulkan_context.hpp"

namespace ikebana::game {

struct WindowStackOptions {
    std::uint32_t width = 1280, height = 720;
    render::StereoMode mode = render::StereoMode::side_by_side;
    bool validation = false;
    // Without the interface layer the stack still opens (the trainee's session then has no panel);
    // with this set its failure is an error.
    bool need_ui = false;
    // Anti-aliasing, samples a pixel; 0: automatic (4 on a graphics card; none on a CPU renderer such
    // as lavapipe, where 4 samples take the eyes' pass from about 15 to 44 ms a frame at 1280x720 per
    // eye and the window would fall below 30 Hz: docs/benchmarks.md).
    std::uint32_t msaa = 0;
    // Every mesh as modelled, however few pixels it covers (RendererOptions::coarse_below_px 0).
    bool full_detail = false;
};

class WindowStack {
public:
    // On an opened window (a caller without one renders offscreen instead). Errors are Vulkan's.
    static Result<std::unique_ptr<WindowStack>> open(std::unique_ptr<platform::Window> window, const WindowStackOptions& options);
    ~WindowStack();
    WindowStack(const WindowStack&) = delete;
    WindowStack& operator=(const WindowStack&) = delete;

    // The list seen from the rig, with the interface over it. Nothing (no error) while minimised.
    Result<std::optional<render::PresentedFrame>> present(const render::DrawList& list, const render::StereoRig& rig, bool screenshot);

    [[nodiscard]] platform::Window& window() { return *window_; }
    [[nodiscard]] render::VulkanContext& vulkan() { return *ctx_; }
    [[nodiscard]] render::StereoRenderer& renderer() { return *renderer_; }
    [[nodiscard]] platform::GlfwPointerSource& pointer() { return *pointer_; }
    [[nodiscard]] render::UiLayer* ui() { return ui_.get(); } // null without the interface
    [[nodiscard]] render::StereoMode mode() const { return mode_; }
    // Another way of showing the scene from the next frame (the eyes are fitted to the window again).
    Result<void> set_mode(render::StereoMode mode);
    // Why the interface is missing (empty when it is there).
    [[nodiscard]] const std::string& ui_problem() const { return ui_problem_; }

private:
    WindowStack() = default;
    std::unique_ptr<platform::Window> window_;
    std::unique_ptr<render::VulkanContext> ctx_;
    VkSurfaceKHR surface_ = VK_NULL_HANDLE;
    std::unique_ptr<render::Swapchain> swapchain_;
    std::unique_ptr<render::StereoRenderer> renderer_;
    std::unique_ptr<platform::GlfwPointerSource> pointer_;
    std::unique_ptr<render::UiLayer> ui_; // after the pointer: its GLFW backend chains to the pointer's callbacks
    render::StereoMode mode_ = render::StereoMode::side_by_side;
    std::string ui_problem_;
};

} // namespace ikebana::game
