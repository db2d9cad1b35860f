#include "game/app/window_stack.hpp"

#include <algorithm>

#include "game/meshes/procedural_meshes.hpp"
#include "game/asset_paths.hpp"

namespace ikebana::game {

Result<std::unique_ptr<WindowStack>> WindowStack::open(std::unique_ptr<platform::Window> window, const WindowStackOptions& o) {
    auto s = std::unique_ptr<WindowStack>(new WindowStack());
    s->window_ = std::move(window);
    s->mode_ = o.mode;
    auto ctx = render::VulkanContext::create(
        {.validation = o.validation, .require_validation = false, .instance_extensions = platform::Window::required_instance_extensions()});
    if (!ctx) return std::move(ctx).error();
    s->ctx_ = std::move(ctx).value();
    auto surface = s->window_->create_surface(s->ctx_->instance());
    if (!surface) return std::move(surface).error();
    s->surface_ = *surface;
    auto swapchain = render::Swapchain::create(*s->ctx_, s->surface_, s->window_->framebuffer());
    if (!swapchain) return std::move(swapchain).error();
    s->swapchain_ = std::move(swapchain).value();
    render::RendererOptions ro;
    ro.mode = o.mode;
    ro.asset_dir = asset_dir();
    ro.generated_mesh = part_mesh_of_name; // a petal or leaf a species draws without a file
    ro.eye_width = std::max(1u, o.mode == render::StereoMode::side_by_side ? o.width / 2 : o.width);
    ro.eye_height = std::max(1u, o.height);
    VkPhysicalDeviceProperties props;
    vkGetPhysicalDeviceProperties(s->ctx_->physical_device(), &props);
    const bool cpu = props.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU; // lavapipe, SwiftShader: they rasterize on the CPU
    ro.msaa_samples = o.msaa != 0 ? o.msaa : (cpu ? 1u : 4u);
    if (o.full_detail) ro.coarse_below_px = 0.0;
    // The eyes in the window's own format: side by side then reaches it as a plain copy.
    if (s->swapchain_->format() == VK_FORMAT_B8G8R8A8_UNORM || s->swapchain_->format() == VK_FORMAT_R8G8B8A8_UNORM) ro.colour_format = s->swapchain_->format();
    auto renderer = render::StereoRenderer::create(*s->ctx_, ro);
    if (!renderer) return std::move(renderer).error();
    s->renderer_ = std::move(renderer).value();
    s->pointer_ = std::make_unique<platform::GlfwPointerSource>(s->window_->glfw());
    // After the pointer's callbacks: ImGui's GLFW backend passes every event on to them.
    auto ui = render::UiLayer::create(*s->ctx_, s->window_->glfw(), s->swapchain_->format(), s->swapchain_->image_count() + ro.frames_in_flight);
    if (!ui) {
        if (o.need_ui) return std::move(ui).error();
        s->ui_problem_ = ui.error().message;
    } else {
        s->ui_ = std::move(ui).value();
        s->renderer_->set_ui(s->ui_.get());
    }
    return s;
}

Result<void> WindowStack::set_mode(render::StereoMode mode) {
    if (auto r = renderer_->set_mode(mode); !r) return r;
    mode_ = mode;
    return {};
}

WindowStack::~WindowStack() {
    if (ctx_ && ctx_->device()) vkDeviceWaitIdle(ctx_->device());
    ui_.reset();
    pointer_.reset();
    renderer_.reset();
    swapchain_.reset();
    if (surface_) vkDestroySurfaceKHR(ctx_->instance(), surface_, nullptr);
    ctx_.reset();
    window_.reset();
}

Result<std::optional<render::PresentedFrame>> WindowStack::present(const render::DrawList& list, const render::StereoRig& rig, bool screenshot) {
    const VkExtent2D size = window_->framebuffer();
    if (size.width == 0 || size.height == 0) return std::optional<render::PresentedFrame>{}; // minimised
    if (size.width != swapchain_->extent().width || size.height != swapchain_->extent().height) {
        if (ui_) ui_->forget_targets();
        if (auto r = swapchain_->recreate(size); !r) return std::move(r).error();
    }
    auto frame = renderer_->present(*swapchain_, list, rig, screenshot);
    if (!frame) return std::move(frame).error();
    if (frame->swapchain_stale) {
        if (ui_) ui_->forget_targets();
        if (auto r = swapchain_->recreate(window_->framebuffer()); !r && window_->framebuffer().width > 0) return std::move(r).error();
    }
    return std::optional<render::PresentedFrame>(std::move(frame).value());
}

} // namespace ikebana::game
