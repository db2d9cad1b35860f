#pragma once
// Dear ImGui (Debian's libimgui-dev 1.86, its GLFW and Vulkan backends) over the composed frame: the
// start screen and the in-session panels. Its Vulkan backend draws inside a render pass, so the layer
// owns one (load the composed image, draw, keep it as a colour attachment) and a framebuffer per
// window image; the renderer calls record() after the composite and before the image is handed to
// the window.
//
// Readable in every stereo mode: side by side, the interface is laid out for one eye and drawn into
// both halves at the same place (zero parallax), and the pointer is read in whichever half it is in;
// interleaved rows, anaglyph and mono draw it once over the whole window (both eyes see the same
// pixels: zero parallax again).
#include <cstdint>
#include <map>
#include <memory>

#include <vulkan/vulkan.h>

#include "engine/core/result.hpp"
#include "engine/render/stereo_renderer.hpp"

struct GLFWwindow;
struct ImDrawList;

namespace ikebana::render {

class VulkanContext;

class UiLayer {
public:
    // After the window's own callbacks are installed (the GLFW backend chains to them, so the hands
    // still get every key). `images` is how many frames may be in flight at once.
    static Result<std::unique_ptr<UiLayer>> create(VulkanContext& ctx, GLFWwindow* window, VkFormat format, std::uint32_t images);
    ~UiLayer();
    UiLayer(const UiLayer&) = delete;
    UiLayer& operator=(const UiLayer&) = delete;

    // A frame of the interface: begin, then ImGui calls (laid out in one eye's size), then end.
    void begin_frame(StereoMode mode);
    void end_frame();
    // Inside the frame's command buffer, the composed image in COLOR_ATTACHMENT_OPTIMAL (it stays so).
    void record(VkCommandBuffer cmd, VkImageView view, VkExtent2D extent);
    // The window's images were made again: their framebuffers go.
    void forget_targets();
    // The pointer is over the interface (a press there is not a grab).
    [[nodiscard]] bool wants_pointer() const;

private:
    UiLayer(VulkanContext& ctx, GLFWwindow* window) : ctx_(ctx), window_(window) {}
    Result<void> init(VkFormat format, std::uint32_t images);
    Result<void> upload_fonts();

    VulkanContext& ctx_;
    GLFWwindow* window_;
    VkRenderPass pass_ = VK_NULL_HANDLE;
    VkDescriptorPool pool_ = VK_NULL_HANDLE;
    std::map<VkImageView, std::pair<VkFramebuffer, VkExtent2D>> framebuffers_;
    StereoMode mode_ = StereoMode::mono;
    bool imgui_ = false, glfw_ = false, vulkan_ = false, framed_ = false;
};

} // namespace ikebana::render
