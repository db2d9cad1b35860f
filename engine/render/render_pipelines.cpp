// The renderer's pipelines: the scene (both eyes in one multiview pass, or one eye per pass), the
// shadow map, and the screen-space ones (composite, heads-up display), one per output format.
#include <cstddef>
#include <utility>
#include <string>

#include "engine/render/pipeline_builder.hpp"
#include "engine/render/renderer_internal.hpp"
#include "engine/render/stereo_renderer.hpp"

namespace ikebana::render {

using detail::CompositeConstants;
using detail::depth_format;
using detail::OverlayConstants;
using detail::Vertex;

namespace {

// A mesh's vertices (binding 0) and its instances (binding 1: the model matrix's columns, a colour).
const VkVertexInputBindingDescription mesh_bindings[2] = {{0, sizeof(Vertex), VK_VERTEX_INPUT_RATE_VERTEX},
                                                          {1, sizeof(MeshInstance), VK_VERTEX_INPUT_RATE_INSTANCE}};
const VkVertexInputAttributeDescription mesh_attributes[10] = {
    {0, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(Vertex, position)}, {1, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(Vertex, normal)},
    {2, 1, VK_FORMAT_R32G32B32A32_SFLOAT, 0},                       {3, 1, VK_FORMAT_R32G32B32A32_SFLOAT, 16},
    {4, 1, VK_FORMAT_R32G32B32A32_SFLOAT, 32},                      {5, 1, VK_FORMAT_R32G32B32A32_SFLOAT, 48},
    {6, 1, VK_FORMAT_R32G32B32A32_SFLOAT, offsetof(MeshInstance, colour)},
    {7, 0, VK_FORMAT_R32G32_SFLOAT, offsetof(Vertex, uv)},          {8, 0, VK_FORMAT_R32G32B32A32_SFLOAT, offsetof(Vertex, tangent)},
    {9, 1, VK_FORMAT_R32_SFLOAT, offsetof(MeshInstance, bend_rad_per_unit)}};
// The shadow's: positions, model matrices and bends only; normals and colours mean nothing to depth.
const VkVertexInputAttributeDescription shadow_attributes[6] = {mesh_attributes[0], mesh_attributes[2], mesh_attributes[3], mesh_attributes[4],
                                                                mesh_attributes[5], mesh_attributes[9]};

// A heads-up panel's vertices: pixel position, 8-bit colour.
const VkVertexInputBindingDescription overlay_binding{0, sizeof(OverlayVertex), VK_VERTEX_INPUT_RATE_VERTEX};
const VkVertexInputAttributeDescription overlay_attributes[2] = {{0, 0, VK_FORMAT_R32G32B32_SFLOAT, 0},
                                                                 {1, 0, VK_FORMAT_R8G8B8A8_UNORM, offsetof(OverlayVertex, colour)}};

// `made` kept in `pipeline`, or its error.
Result<void> keep(Result<VkPipeline> made, VkPipeline& pipeline) {
    if (!made) return std::move(made).error();
    pipeline = *made;
    return Ok{};
}

} // namespace

Result<void> StereoRenderer::prepare_pipelines() {
    ShaderModules shaders(ctx_, options_.shader_dir); // destroyed once every pipeline is made
    VkShaderModule modules[6] = {};
    const char* names[6] = {"mesh.vert.spv", "mesh.frag.spv", "shadow.vert.spv", "mesh_material.frag.spv", "mesh_masked.frag.spv", "mesh_material.vert.spv"};
    for (int i = 0; i < 6; ++i) {
        auto m = shaders.load(names[i]);
        if (!m) return std::move(m).error();
        modules[i] = *m;
    }
    // Set 0 the frame's (uniforms, shadow map), set 1 the material's pictures; the eye and the
    // material's factors in one push-constant range.
    const VkPushConstantRange scene_push{VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof(SceneConstants)};
    const VkDescriptorSetLayout scene_sets[2] = {scene_layout_, material_layout_};
    VkPipelineLayoutCreateInfo scene_layout{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO, nullptr, 0, 2, scene_sets, 1, &scene_push};
    IKEBANA_VK(vkCreatePipelineLayout(ctx_.device(), &scene_layout, nullptr, &scene_pipeline_layout_));
    const VkPushConstantRange push{VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof(CompositeConstants)};
    VkPipelineLayoutCreateInfo composite_layout{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO, nullptr, 0, 1, &composite_layout_, 1, &push};
    IKEBANA_VK(vkCreatePipelineLayout(ctx_.device(), &composite_layout, nullptr, &composite_pipeline_layout_));

    // Scene: both eyes at once, then the same for one eye per pass. Culling is set per batch (closed
    // meshes cull their back faces; petals and leaves are single sheets).
    GraphicsPipelineBuilder scene("scene");
    scene.shaders({shader_stage(VK_SHADER_STAGE_VERTEX_BIT, modules[0]), shader_stage(VK_SHADER_STAGE_FRAGMENT_BIT, modules[1])})
        .vertex_input(mesh_bindings, mesh_attributes)
        .colour_formats({options_.colour_format})
        .depth_format(depth_format)
        .depth_test(VK_COMPARE_OP_LESS, true)
        .dynamic_cull_mode()
        .samples(samples_);
    if (auto ok = keep(scene.view_mask(0b11).build(ctx_.device(), scene_pipeline_layout_), scene_pipeline_); !ok) return ok;
    if (auto ok = keep(scene.name("per-eye scene").view_mask(0).build(ctx_.device(), scene_pipeline_layout_), per_eye_pipeline_); !ok) return ok;
    // Parts with a material, then alpha-masked ones: the same with mesh.frag's other variants.
    const std::pair<VkShaderModule, VkPipeline*> variants[2][2] = {{{modules[3], &material_pipeline_}, {modules[3], &per_eye_material_pipeline_}},
                                                                   {{modules[4], &masked_pipeline_}, {modules[4], &per_eye_masked_pipeline_}}};
    for (const auto& [multiview_one, per_eye_one] : variants) {
        scene.shaders({shader_stage(VK_SHADER_STAGE_VERTEX_BIT, modules[5]), shader_stage(VK_SHADER_STAGE_FRAGMENT_BIT, multiview_one.first)});
        if (auto ok = keep(scene.name("material scene").view_mask(0b11).build(ctx_.device(), scene_pipeline_layout_), *multiview_one.second); !ok) return ok;
        if (auto ok = keep(scene.name("per-eye material scene").view_mask(0).build(ctx_.device(), scene_pipeline_layout_), *per_eye_one.second); !ok) return ok;
    }
    scene.shaders({shader_stage(VK_SHADER_STAGE_VERTEX_BIT, modules[0]), shader_stage(VK_SHADER_STAGE_FRAGMENT_BIT, modules[1])});
    // Translucent batches (water, ghosts): blended, tested against the depth but not written to it.
    scene.blend(alpha_blend()).depth_test(VK_COMPARE_OP_LESS, false);
    if (auto ok = keep(scene.name("translucent scene").view_mask(0b11).build(ctx_.device(), scene_pipeline_layout_), translucent_pipeline_); !ok) return ok;
    if (auto ok = keep(scene.name("per-eye translucent scene").view_mask(0).build(ctx_.device(), scene_pipeline_layout_), per_eye_translucent_pipeline_); !ok) {
        return ok;
    }

    // Shadow: depth only, from the light, with a slope bias against acne.
    GraphicsPipelineBuilder shadow("shadow");
    shadow.shaders({shader_stage(VK_SHADER_STAGE_VERTEX_BIT, modules[2])})
        .vertex_input(mesh_bindings, shadow_attributes)
        .depth_format(depth_format)
        .depth_test(VK_COMPARE_OP_LESS, true)
        .depth_bias(1.25f, 1.75f)
        .dynamic_cull_mode();
    if (auto ok = keep(shadow.build(ctx_.device(), scene_pipeline_layout_), shadow_pipeline_); !ok) return ok;
    return keep(make_composite_pipeline(options_.colour_format), composite_pipeline_);
}

// A screen-space pipeline (no depth, no culling) drawing into one colour target of this format: the
// composite and the heads-up display differ only in their shaders, vertex input, blending and layout.
Result<VkPipeline> StereoRenderer::make_screen_pipeline(VkFormat format, const char* shader, GraphicsPipelineBuilder& pipeline, VkPipelineLayout layout) {
    ShaderModules shaders(ctx_, options_.shader_dir);
    auto vert = shaders.load(std::string(shader) + ".vert.spv");
    if (!vert) return std::move(vert).error();
    auto frag = shaders.load(std::string(shader) + ".frag.spv");
    if (!frag) return std::move(frag).error();
    pipeline.shaders({shader_stage(VK_SHADER_STAGE_VERTEX_BIT, *vert), shader_stage(VK_SHADER_STAGE_FRAGMENT_BIT, *frag)}).colour_formats({format});
    return pipeline.build(ctx_.device(), layout);
}

// Composite: one triangle, the eyes to an output of this format (offscreen, or the window's).
Result<VkPipeline> StereoRenderer::make_composite_pipeline(VkFormat format) {
    GraphicsPipelineBuilder composite("composite");
    composite.blend(colour_write_all());
    return make_screen_pipeline(format, "composite", composite, composite_pipeline_layout_);
}

// Heads-up panels: pixel-space triangles with their own colours, alpha-blended over the frame.
Result<VkPipeline> StereoRenderer::make_overlay_pipeline(VkFormat format) {
    if (!overlay_layout_) {
        const VkPushConstantRange push{VK_SHADER_STAGE_VERTEX_BIT, 0, sizeof(OverlayConstants)};
        VkPipelineLayoutCreateInfo layout{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO, nullptr, 0, 0, nullptr, 1, &push};
        IKEBANA_VK(vkCreatePipelineLayout(ctx_.device(), &layout, nullptr, &overlay_layout_));
    }
    GraphicsPipelineBuilder overlay("overlay");
    overlay.vertex_input({&overlay_binding, 1}, overlay_attributes).blend(alpha_blend());
    return make_screen_pipeline(format, "overlay", overlay, overlay_layout_);
}

// No panels: no pipeline (and nothing drawn).
Result<VkPipeline> StereoRenderer::overlay_pipeline_for(VkFormat format) {
    if (overlay_.empty()) return VkPipeline{VK_NULL_HANDLE};
    return cached_pipeline(overlay_pipelines_, format, &StereoRenderer::make_overlay_pipeline);
}

Result<VkPipeline> StereoRenderer::composite_pipeline_for(VkFormat format) {
    if (format == options_.colour_format) return composite_pipeline_;
    return cached_pipeline(window_composite_, format, &StereoRenderer::make_composite_pipeline);
}

// One pipeline per output format, made on first use.
Result<VkPipeline> StereoRenderer::cached_pipeline(std::map<VkFormat, VkPipeline>& cache, VkFormat format,
                                                   Result<VkPipeline> (StereoRenderer::*make)(VkFormat)) {
    if (auto it = cache.find(format); it != cache.end()) return it->second;
    auto made = (this->*make)(format);
    if (!made) return std::move(made).error();
    cache[format] = *made;
    return *made;
}

} // namespace ikebana::render
