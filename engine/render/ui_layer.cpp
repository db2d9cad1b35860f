#include "engine/render/ui_layer.hpp"

#include <filesystem>
#include <vector>

#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui/backends/imgui_impl_glfw.h>
#include <imgui/backends/imgui_impl_vulkan.h>

#include "engine/render/vulkan_context.hpp"

namespace ikebana::render {
namespace {

Error vk_error(const char* what, VkResult r) {
    return make_error(ErrorCode::device_error, std::string("the interface layer: ") + what + " failed (VkResult " + std::to_string(static_cast<int>(r)) + ")");
}

// Draw lists moved by (dx, dy): the same interface for the other eye.
ImDrawList* shifted_copy(const ImDrawList* list, float dx, float dy) {
    ImDrawList* copy = list->CloneOutput();
    for (auto& v : copy->VtxBuffer) {
        v.pos.x += dx;
        v.pos.y += dy;
    }
    for (auto& c : copy->CmdBuffer) {
        c.ClipRect.x += dx;
        c.ClipRect.z += dx;
        c.ClipRect.y += dy;
        c.ClipRect.w += dy;
    }
    return copy;
}

} // namespace

Result<std::unique_ptr<UiLayer>> UiLayer::create(VulkanContext& ctx, GLFWwindow* window, VkFormat format, std::uint32_t images) {
    std::unique_ptr<UiLayer> layer(new UiLayer(ctx, window));
    if (auto r = layer->init(format, images); !r) return r.error();
    return layer;
}

Result<void> UiLayer::init(VkFormat format, std::uint32_t images) {
    // Load what the composite drew, draw over it, leave it a colour attachment for the hand-over.
    VkAttachmentDescription colour{};
    colour.format = format;
    colour.samples = VK_SAMPLE_COUNT_1_BIT;
    colour.loadOp = VK_ATTACHMENT_LOAD_OP_LOAD;
    colour.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    colour.stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
    colour.stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
    colour.initialLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    colour.finalLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    VkAttachmentReference ref{0, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
    VkSubpassDescription subpass{};
    subpass.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
    subpass.colorAttachmentCount = 1;
    subpass.pColorAttachments = &ref;
    // After the composite's writes (and the eyes' copy into the image).
    VkSubpassDependency after{};
    after.srcSubpass = VK_SUBPASS_EXTERNAL;
    after.dstSubpass = 0;
    after.srcStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT;
    after.srcAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
    after.dstStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;
    after.dstAccessMask = VK_ACCESS_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
    VkRenderPassCreateInfo info{VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO};
    info.attachmentCount = 1;
    info.pAttachments = &colour;
    info.subpassCount = 1;
    info.pSubpasses = &subpass;
    info.dependencyCount = 1;
    info.pDependencies = &after;
    if (VkResult r = vkCreateRenderPass(ctx_.device(), &info, nullptr, &pass_); r != VK_SUCCESS) return vk_error("vkCreateRenderPass", r);

    const VkDescriptorPoolSize sizes[] = {{VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 8}};
    VkDescriptorPoolCreateInfo pool{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    pool.flags = VK_DESCRIPTOR_POOL_CREATE_FREE_DESCRIPTOR_SET_BIT;
    pool.maxSets = 8;
    pool.poolSizeCount = 1;
    pool.pPoolSizes = sizes;
    if (VkResult r = vkCreateDescriptorPool(ctx_.device(), &pool, nullptr, &pool_); r != VK_SUCCESS) return vk_error("vkCreateDescriptorPool", r);

    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    imgui_ = true;
    ImGuiIO& io = ImGui::GetIO();
    io.IniFilename = nullptr; // the layout is the program's, not a file beside the trainee's work
    io.LogFilename = nullptr;
    ImGui::StyleColorsLight();
    ImGuiStyle& style = ImGui::GetStyle();
    style.WindowRounding = 6.0f;
    style.FrameRounding = 4.0f;
    style.WindowPadding = ImVec2(14.0f, 12.0f);
    style.ItemSpacing = ImVec2(8.0f, 6.0f);
    const char* sans = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";
    std::error_code ec;
    if (std::filesystem::exists(sans, ec)) io.Fonts->AddFontFromFileTTF(sans, 16.0f);
    else io.FontGlobalScale = 1.25f; // ImGui's own font, larger
    if (!ImGui_ImplGlfw_InitForVulkan(window_, true)) return make_error(ErrorCode::device_error, "the interface layer: its GLFW backend did not start");
    glfw_ = true;
    ImGui_ImplVulkan_InitInfo vk{};
    vk.Instance = ctx_.instance();
    vk.PhysicalDevice = ctx_.physical_device();
    vk.Device = ctx_.device();
    vk.QueueFamily = ctx_.queue_family();
    vk.Queue = ctx_.queue();
    vk.DescriptorPool = pool_;
    vk.Subpass = 0;
    // ImGui keeps a vertex buffer per image it is given, in turn: one more than may be in flight.
    vk.MinImageCount = std::max(2u, images);
    vk.ImageCount = std::max(2u, images) + 1;
    vk.MSAASamples = VK_SAMPLE_COUNT_1_BIT;
    if (!ImGui_ImplVulkan_Init(&vk, pass_)) return make_error(ErrorCode::device_error, "the interface layer: its Vulkan backend did not start");
    vulkan_ = true;
    return upload_fonts();
}

Result<void> UiLayer::upload_fonts() {
    VkCommandPoolCreateInfo pool_info{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    pool_info.flags = VK_COMMAND_POOL_CREATE_TRANSIENT_BIT;
    pool_info.queueFamilyIndex = ctx_.queue_family();
    VkCommandPool pool = VK_NULL_HANDLE;
    if (VkResult r = vkCreateCommandPool(ctx_.device(), &pool_info, nullptr, &pool); r != VK_SUCCESS) return vk_error("vkCreateCommandPool", r);
    VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    alloc.commandPool = pool;
    alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    alloc.commandBufferCount = 1;
    VkCommandBuffer cmd = VK_NULL_HANDLE;
    VkResult r = vkAllocateCommandBuffers(ctx_.device(), &alloc, &cmd);
    if (r == VK_SUCCESS) {
        VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
        begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
        vkBeginCommandBuffer(cmd, &begin);
        ImGui_ImplVulkan_CreateFontsTexture(cmd);
        vkEndCommandBuffer(cmd);
        VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
        submit.commandBufferCount = 1;
        submit.pCommandBuffers = &cmd;
        r = vkQueueSubmit(ctx_.queue(), 1, &submit, VK_NULL_HANDLE);
        if (r == VK_SUCCESS) r = vkQueueWaitIdle(ctx_.queue());
    }
    ImGui_ImplVulkan_DestroyFontUploadObjects();
    vkDestroyCommandPool(ctx_.device(), pool, nullptr);
    if (r != VK_SUCCESS) return vk_error("uploading the font", r);
    return {};
}

UiLayer::~UiLayer() {
    if (ctx_.device()) vkDeviceWaitIdle(ctx_.device());
    forget_targets();
    if (vulkan_) ImGui_ImplVulkan_Shutdown();
    if (glfw_) ImGui_ImplGlfw_Shutdown(); // gives the window its own callbacks back
    if (imgui_) ImGui::DestroyContext();
    if (pool_) vkDestroyDescriptorPool(ctx_.device(), pool_, nullptr);
    if (pass_) vkDestroyRenderPass(ctx_.device(), pass_, nullptr);
}

void UiLayer::forget_targets() {
    // A framebuffer may still be in use by a frame in flight (the swapchain's own wait comes later).
    if (!framebuffers_.empty() && ctx_.device()) vkDeviceWaitIdle(ctx_.device());
    for (auto& [view, fb] : framebuffers_) vkDestroyFramebuffer(ctx_.device(), fb.first, nullptr);
    framebuffers_.clear();
}

void UiLayer::begin_frame(StereoMode mode) {
    mode_ = mode;
    ImGui_ImplVulkan_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    // Laid out for one eye: side by side, half the window, and the pointer read in the half it is in
    // (ImGui's backend reads it only while the window has the focus; ours always does).
    ImGuiIO& io = ImGui::GetIO();
    int width = 1, height = 1;
    glfwGetWindowSize(window_, &width, &height);
    double x = 0.0, y = 0.0;
    glfwGetCursorPos(window_, &x, &y);
    const float eye_width = mode == StereoMode::side_by_side ? 0.5f * static_cast<float>(width) : static_cast<float>(width);
    io.DisplaySize = ImVec2(eye_width, static_cast<float>(height));
    io.MousePos = ImVec2(static_cast<float>(x) >= eye_width ? static_cast<float>(x) - eye_width : static_cast<float>(x), static_cast<float>(y));
    ImGui::NewFrame();
    framed_ = true;
}

void UiLayer::end_frame() {
    if (!framed_) return;
    ImGui::Render();
}

bool UiLayer::wants_pointer() const { return imgui_ && ImGui::GetIO().WantCaptureMouse; }

void UiLayer::record(VkCommandBuffer cmd, VkImageView view, VkExtent2D extent) {
    if (!framed_) return;
    framed_ = false;
    ImDrawData* drawn = ImGui::GetDrawData();
    if (!drawn || !drawn->Valid || drawn->CmdListsCount == 0) return;
    auto fb = framebuffers_.find(view);
    if (fb != framebuffers_.end() && (fb->second.second.width != extent.width || fb->second.second.height != extent.height)) {
        vkDeviceWaitIdle(ctx_.device()); // an earlier frame in flight may still draw into it
        vkDestroyFramebuffer(ctx_.device(), fb->second.first, nullptr);
        framebuffers_.erase(fb);
        fb = framebuffers_.end();
    }
    if (fb == framebuffers_.end()) {
        VkFramebufferCreateInfo info{VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO};
        info.renderPass = pass_;
        info.attachmentCount = 1;
        info.pAttachments = &view;
        info.width = extent.width;
        info.height = extent.height;
        info.layers = 1;
        VkFramebuffer made = VK_NULL_HANDLE;
        if (vkCreateFramebuffer(ctx_.device(), &info, nullptr, &made) != VK_SUCCESS) return;
        fb = framebuffers_.emplace(view, std::make_pair(made, extent)).first;
    }
    if (drawn->DisplaySize.x <= 0.0f || drawn->DisplaySize.y <= 0.0f) return;
    // Side by side: the same lists again in the right half.
    std::vector<ImDrawList*> lists(drawn->CmdLists, drawn->CmdLists + drawn->CmdListsCount);
    std::vector<ImDrawList*> copies;
    ImDrawData both = *drawn;
    if (mode_ == StereoMode::side_by_side) {
        for (int i = 0; i < drawn->CmdListsCount; ++i) copies.push_back(shifted_copy(drawn->CmdLists[i], drawn->DisplaySize.x, 0.0f));
        lists.insert(lists.end(), copies.begin(), copies.end());
        both.CmdLists = lists.data();
        both.CmdListsCount = static_cast<int>(lists.size());
        both.TotalIdxCount *= 2;
        both.TotalVtxCount *= 2;
        both.DisplaySize.x *= 2.0f;
    }
    // Laid out in the window's size when the frame began; drawn into the image's size now. They
    // differ for a frame after a resize, and the backend's scissors must stay inside the image.
    both.FramebufferScale = ImVec2(static_cast<float>(extent.width) / both.DisplaySize.x, static_cast<float>(extent.height) / both.DisplaySize.y);
    VkRenderPassBeginInfo begin{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
    begin.renderPass = pass_;
    begin.framebuffer = fb->second.first;
    begin.renderArea.extent = extent;
    vkCmdBeginRenderPass(cmd, &begin, VK_SUBPASS_CONTENTS_INLINE);
    ImGui_ImplVulkan_RenderDrawData(&both, cmd);
    vkCmdEndRenderPass(cmd);
    for (auto* c : copies) IM_DELETE(c);
}

} // namespace ikebana::render
