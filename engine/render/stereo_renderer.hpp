#pragma once
// Both eyes in one pass (multiview, viewMask 0b11) into a two-layer image, with a shadow map, then a
// composite pass to the display's format: side by side, row-interleaved (the paper's polarized
// display), anaglyph red-cyan, or mono. Offscreen: the composed frame (and each eye) is read back.
// Structure after Sascha Willems' examples: short prepare_*() steps; a resize recreates only the
// size-dependent targets; per-frame resources live in arrays of frames in flight. One class in four
// files: set-up and frames here (stereo_renderer.cpp), a function per pass (render_passes.cpp), the
// pipelines (render_pipelines.cpp, with pipeline_builder.hpp), the meshes (render_meshes.cpp).
#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "engine/core/result.hpp"
#include "engine/assets/mesh.hpp"
#include "engine/render/draw_list.hpp"
#include "engine/render/gpu_resources.hpp"
#include "engine/render/png_image.hpp"
#include "engine/render/stereo_camera.hpp"
#include "engine/render/swapchain.hpp"
#include "engine/render/text_overlay.hpp"
#include "engine/render/vulkan_context.hpp"

namespace ikebana::render {

class UiLayer;

class GraphicsPipelineBuilder;

enum class StereoMode { side_by_side, rows, anaglyph, mono };
Result<StereoMode> parse_stereo_mode(std::string_view text); // sbs, rows, anaglyph, mono
const char* stereo_mode_name(StereoMode mode);

// $IKEBANA_SHADERS, else the build tree's compiled shaders.
std::filesystem::path default_shader_dir();

struct RendererOptions {
    std::uint32_t eye_width = 1280;
    std::uint32_t eye_height = 720;
    StereoMode mode = StereoMode::side_by_side;
    std::filesystem::path shader_dir = default_shader_dir(); // the .spv files
    std::filesystem::path asset_dir;   // glTF mesh names are relative to it
    std::uint32_t frames_in_flight = 2;
    std::uint32_t shadow_map_size = 1024;
    // The eyes' and the offscreen output's format: R8G8B8A8 or B8G8R8A8 (UNORM). A window should pass
    // its swapchain's, so that side by side reaches it as a plain copy: on lavapipe a blit that swaps
    // red and blue costs about 5 ms a frame at 2560x720.
    VkFormat colour_format = VK_FORMAT_R8G8B8A8_UNORM;
    // Both eyes in one multiview pass, or one pass per eye. Automatic: multiview, except on lavapipe,
    // whose multiview (Mesa 22.3) loses triangles clipped at the frustum in the second view.
    enum class Multiview { automatic, on, off } multiview = Multiview::automatic;
    // Anti-aliasing: the eyes are drawn with this many samples a pixel (multisampling) and resolved
    // before they are composed, so every stereo mode gets it. The device's nearest count at or below
    // it; 1: none.
    std::uint32_t msaa_samples = 4;
    // Kept on the right of each eye's area for a window's panels (render::ScreenLayout): the eyes are
    // drawn beside it, never under text. A window's eyes are the rest of its area.
    std::uint32_t column_px = 0;
    // Meshes the program makes rather than reads: asked first for every mesh name, a mesh for the names
    // it knows (a species' petal or leaf drawn without a file), nothing for a file's name. May be empty.
    std::function<std::optional<assets::MeshData>(const std::string&)> generated_mesh;
    // Level of detail (mesh_lod.hpp): an instance shorter than this on screen is drawn with its mesh's
    // coarse copy, merged on a grid of `coarse_cells` along the mesh's longest side (about 5 px a cell
    // at the threshold). 0: every instance as modelled.
    double coarse_below_px = 40.0;
    int coarse_cells = 8;
};

struct FrameTiming {
    double record_ms = 0.0;   // CPU: filling instances and recording commands
    double execute_ms = 0.0;  // submit to fence: the device's work (lavapipe: CPU threads)
    double readback_ms = 0.0; // copying pixels out
    // From device timestamps, where the device's time goes (of this frame offscreen; of the frame
    // that last used this slot in a window, since presenting does not wait). Zero when unsupported.
    double shadow_ms = 0.0;
    double scene_ms = 0.0;     // both eyes
    double composite_ms = 0.0; // composite and heads-up display
    double present_ms = 0.0;   // window: acquiring the image and queueing it for presentation (CPU)
    // Triangles sent to one eye's pass and to the shadow pass, after level of detail: on lavapipe these,
    // not the pixels, set the passes' time.
    std::uint64_t eye_triangles = 0, shadow_triangles = 0;
};

struct PresentedFrame {
    bool presented = false;
    bool swapchain_stale = false; // out of date or suboptimal: recreate it for the window's new size
    std::optional<RgbaImage> screenshot;
    FrameTiming timing;
};

struct RenderedFrame {
    RgbaImage composed;
    RgbaImage left, right; // when asked for
    FrameTiming timing;
};

class StereoRenderer {
public:
    static Result<std::unique_ptr<StereoRenderer>> create(VulkanContext& ctx, const RendererOptions& options);
    ~StereoRenderer();
    StereoRenderer(const StereoRenderer&) = delete;
    StereoRenderer& operator=(const StereoRenderer&) = delete;

    Result<void> resize(std::uint32_t eye_width, std::uint32_t eye_height);
    Result<void> set_mode(StereoMode mode); // the output size depends on it: recreates the targets
    Result<RenderedFrame> render(const DrawList& list, const StereoRig& rig, bool with_eyes);
    // The same frame composed into the window's next image and presented; the eyes follow the
    // window's size. A screenshot reads back what was presented.
    Result<PresentedFrame> present(Swapchain& swapchain, const DrawList& list, const StereoRig& rig, bool screenshot = false);
    // The column kept for panels from the next frame on (RendererOptions::column_px).
    void set_column(std::uint32_t px) noexcept { options_.column_px = px; }
    [[nodiscard]] std::uint32_t column() const noexcept { return options_.column_px; }
    // Heads-up panels drawn over every following frame (in each eye's scene) until replaced.
    void set_overlay(std::vector<OverlayPanel> panels) { overlay_ = std::move(panels); }
    // Dear ImGui's interface over the window's frames (null: none). Not owned.
    void set_ui(UiLayer* ui) { ui_ = ui; }
    [[nodiscard]] VkExtent2D output_extent() const noexcept;
    [[nodiscard]] bool multiview() const noexcept { return multiview_; }
    [[nodiscard]] std::uint32_t samples() const noexcept { return static_cast<std::uint32_t>(samples_); }
    // Placeholder meshes drawn since the last call, each naming its file and why.
    std::vector<std::string> take_warnings();

private:
    // The scene pipelines' push constants: the eye (mesh.vert, shadow.vert) and the material being drawn
    // (mesh.frag). One range for both stages.
    struct SceneConstants {
        std::int32_t eye_base = 0;
        std::int32_t normal_mapped = 0;
        float alpha_cutoff = -1.0f; // negative: opaque
        float normal_scale = 1.0f;
        glm::vec4 base_colour{1.0f}; // times the instance's colour and the base colour texture
        float metallic = 0.0f;
        float roughness = 1.0f;
        std::int32_t textured = 0; // a base colour picture to sample
        float pad = 0.0f;
    };
    // How a part is shaded (which variant of mesh.frag): by its instance's colour alone, with its glTF
    // material, or with its material and alpha mask. The shadow pass draws every part at once.
    enum class Shading { plain, material, masked, any };
    // A run of a mesh's triangles with its material: pictures (set 1) and factors (push constants).
    struct Part {
        std::uint32_t first_index = 0, index_count = 0;
        VkDescriptorSet material = VK_NULL_HANDLE;
        SceneConstants constants;
        Shading shading = Shading::plain;
    };
    struct Mesh {
        GpuBuffer vertices, indices;
        std::uint32_t index_count = 0;
        // A closed surface (the built-in cube and cylinders): its back faces are never seen, so they
        // are culled before lavapipe rasterises them. Petals and leaves are single sheets: no culling.
        bool closed = false;
        std::vector<Part> parts;
        std::vector<GpuImage> textures;                 // the mesh's own pictures
        VkDescriptorPool materials = VK_NULL_HANDLE;    // its parts' sets (none: the default material's)
        // Drawn where an instance is small on screen (RendererOptions::coarse_below_px): its parts
        // use this mesh's materials. None: always this one.
        Mesh* coarse = nullptr;
        // Its bounding box's sides in its own units (mesh_span), for its instances' size on screen.
        glm::vec3 span{1.0f};
    };
    struct Draw {
        Mesh* mesh;
        std::uint32_t instances;
        bool casts_shadow;
        bool translucent;
    };
    struct Frame {
        VkCommandBuffer cmd = VK_NULL_HANDLE;
        VkFence fence = VK_NULL_HANDLE;
        GpuBuffer uniforms, instances, readback;
        VkDescriptorSet scene_set = VK_NULL_HANDLE;
        VkSemaphore image_available = VK_NULL_HANDLE; // window only
        GpuBuffer overlay;                             // the heads-up panels' triangles
        VkQueryPool timestamps = VK_NULL_HANDLE;       // start, after shadow, after scene, after composite
        bool timestamps_written = false;
        std::vector<std::pair<std::uint32_t, std::uint32_t>> overlay_ranges; // first vertex, count per panel
        // Where each panel goes in each area (side by side: the left eye's, the right eye's; else the
        // centre's), nothing where an anchored panel's point is behind the eye.
        std::vector<std::array<std::optional<glm::vec2>, 2>> overlay_origins;
    };
    struct CompositeTarget {
        VkImage image;
        VkImageView view;
        VkExtent2D extent;
        VkPipeline pipeline;
        VkPipeline overlay_pipeline;
        bool read_back;
        bool with_eyes;
        bool present;
        bool blit; // the target takes transfers: side by side and mono are copied, not shaded
        VkFormat format;
    };

    StereoRenderer(VulkanContext& ctx, const RendererOptions& options) : ctx_(ctx), options_(options) {}
    // Set-up, resources and frames (stereo_renderer.cpp).
    Result<void> prepare_frames();
    Result<void> prepare_shadow_map();
    Result<void> prepare_targets();
    Result<void> prepare_descriptors();
    void destroy_targets();
    Result<Frame*> begin_frame(const DrawList& list, const StereoRig& rig);
    void read_back(const Frame& frame, RgbaImage& image, VkExtent2D extent, std::size_t offset, bool bgra) const;
    void read_timestamps(Frame& frame, FrameTiming& timing) const;

    // Pipelines (render_pipelines.cpp).
    Result<void> prepare_pipelines();
    Result<VkPipeline> make_screen_pipeline(VkFormat format, const char* shader, GraphicsPipelineBuilder& pipeline, VkPipelineLayout layout);
    Result<VkPipeline> cached_pipeline(std::map<VkFormat, VkPipeline>& cache, VkFormat format, Result<VkPipeline> (StereoRenderer::*make)(VkFormat));
    Result<VkPipeline> make_composite_pipeline(VkFormat format);
    Result<VkPipeline> make_overlay_pipeline(VkFormat format);
    Result<VkPipeline> overlay_pipeline_for(VkFormat format);
    Result<VkPipeline> composite_pipeline_for(VkFormat format);

    // Meshes and the heads-up panels' triangles (render_meshes.cpp).
    Result<void> prepare_builtin_meshes();
    Result<Mesh*> mesh(const std::string& name);
    Result<Mesh> upload(const assets::MeshData& data);
    Result<void> upload_geometry(const assets::MeshData& data, Mesh& m);
    Result<Mesh> upload_coarse(const assets::MeshData& coarse, const Mesh& fine);
    void add_coarse_copy(const std::string& name, const assets::MeshData& data);
    Result<GpuImage> upload_texture(const assets::DecodedImage& image);
    Result<void> prepare_default_material();
    Result<VkSampler> sampler_for(const assets::TextureSampling& sampling);
    void destroy_mesh(Mesh& mesh);
    Result<void> fill_overlay(Frame& frame);

    // The frame's commands, one function per pass (render_passes.cpp).
    void record(Frame& frame, const DrawList& list, const std::vector<Draw>& draws, const CompositeTarget& target);
    void record_shadow_pass(const Frame& frame, const std::vector<Draw>& draws) const;
    void record_eye_passes(const Frame& frame, const DrawList& list, const std::vector<Draw>& draws, bool both_eyes_wanted) const;
    void clear_eye_depth(VkCommandBuffer cmd) const;
    VkImageLayout record_composite(const Frame& frame, const CompositeTarget& target) const; // the eyes' layout after it
    void copy_eyes_to_target(VkCommandBuffer cmd, const CompositeTarget& target) const;
    void clear_columns(VkCommandBuffer cmd, const CompositeTarget& target) const;
    void draw_composite(VkCommandBuffer cmd, const CompositeTarget& target) const;
    void draw_overlay(const Frame& frame, const CompositeTarget& target) const;
    void record_hand_over(const Frame& frame, const CompositeTarget& target, VkImageLayout eyes_layout) const;
    void copy_eyes_to_host(const Frame& frame, const CompositeTarget& target, VkImageLayout eyes_layout) const;
    void draw_batches(const Frame& frame, const std::vector<Draw>& draws, bool shadow_casters_only, bool translucent, Shading shading = Shading::any) const;

    VulkanContext& ctx_;
    RendererOptions options_;
    VkCommandPool pool_ = VK_NULL_HANDLE;
    std::vector<Frame> frames_;
    std::size_t frame_index_ = 0;
    GpuImage eyes_, depth_, output_, shadow_;
    VkImageView eye_layer_[2] = {}, depth_layer_[2] = {}; // single-layer views for one pass per eye
    VkSampleCountFlagBits samples_ = VK_SAMPLE_COUNT_1_BIT;
    GpuImage eyes_msaa_;                 // with samples_ > 1: drawn into, resolved into eyes_
    VkImageView eye_msaa_layer_[2] = {};
    bool multiview_ = true;
    double timestamp_period_ns_ = 0.0; // 0: the queue cannot time itself
    VkSampler shadow_sampler_ = VK_NULL_HANDLE, eye_sampler_ = VK_NULL_HANDLE;
    // Materials: the pictures' sampler (linear, mipmapped, repeating), the set layout (base colour,
    // normal map), and the default material's white picture, flat normal and set.
    VkSampler material_sampler_ = VK_NULL_HANDLE;
    std::map<assets::TextureSampling, VkSampler> samplers_; // glTF samplers, one per kind
    VkDescriptorSetLayout material_layout_ = VK_NULL_HANDLE;
    GpuImage white_texture_, flat_normal_texture_;
    VkDescriptorPool default_material_pool_ = VK_NULL_HANDLE;
    VkDescriptorSet default_material_ = VK_NULL_HANDLE;
    VkDescriptorSetLayout scene_layout_ = VK_NULL_HANDLE, composite_layout_ = VK_NULL_HANDLE;
    VkDescriptorPool descriptor_pool_ = VK_NULL_HANDLE;
    VkDescriptorSet composite_set_ = VK_NULL_HANDLE;
    VkPipelineLayout scene_pipeline_layout_ = VK_NULL_HANDLE, composite_pipeline_layout_ = VK_NULL_HANDLE;
    VkPipeline scene_pipeline_ = VK_NULL_HANDLE, per_eye_pipeline_ = VK_NULL_HANDLE, shadow_pipeline_ = VK_NULL_HANDLE, composite_pipeline_ = VK_NULL_HANDLE;
    VkPipeline translucent_pipeline_ = VK_NULL_HANDLE, per_eye_translucent_pipeline_ = VK_NULL_HANDLE;
    // Parts with a glTF material of their own, and alpha-masked ones (mesh.frag's variants).
    VkPipeline material_pipeline_ = VK_NULL_HANDLE, per_eye_material_pipeline_ = VK_NULL_HANDLE;
    VkPipeline masked_pipeline_ = VK_NULL_HANDLE, per_eye_masked_pipeline_ = VK_NULL_HANDLE;
    std::map<std::string, Mesh> meshes_;
    std::map<std::string, Mesh> coarse_meshes_; // by their fine mesh's name; pointed to by Mesh::coarse
    std::vector<Draw> draws_;
    std::uint64_t eye_triangles_ = 0, shadow_triangles_ = 0; // of the frame begun last
    std::map<VkFormat, VkPipeline> window_composite_;
    std::map<VkFormat, VkPipeline> overlay_pipelines_;
    VkPipelineLayout overlay_layout_ = VK_NULL_HANDLE;
    std::vector<OverlayPanel> overlay_;
    UiLayer* ui_ = nullptr;
    std::vector<VkSemaphore> render_finished_; // one per window image
    std::vector<std::string> warnings_;
};

} // namespace ikebana::render
