// The frame's commands, one function per pass: shadow map, eyes, composite (and heads-up display),
// then read back and hand over. record() runs them in that order, with a timestamp after each.
#include <algorithm>
#include <cstdint>
#include <vector>

#include "engine/render/renderer_internal.hpp"
#include "engine/render/stereo_renderer.hpp"
#include "engine/render/ui_layer.hpp"

namespace ikebana::render {

using detail::CompositeConstants;
using detail::OverlayConstants;

namespace {

constexpr auto none = VK_PIPELINE_STAGE_2_NONE;

void set_viewport(VkCommandBuffer cmd, VkExtent2D e) {
    VkViewport v{0.0f, 0.0f, static_cast<float>(e.width), static_cast<float>(e.height), 0.0f, 1.0f};
    VkRect2D s{{0, 0}, e};
    vkCmdSetViewport(cmd, 0, 1, &v);
    vkCmdSetScissor(cmd, 0, 1, &s);
}

// Query 1 after the shadow map, 2 after the eyes, 3 after the composite (0 is the start).
void write_timestamp(VkCommandBuffer cmd, VkQueryPool pool, std::uint32_t query) {
    if (pool) vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_ALL_GRAPHICS_BIT, pool, query);
}

VkClearValue far_depth() {
    VkClearValue clear{};
    clear.depthStencil = {1.0f, 0};
    return clear;
}

VkRenderingAttachmentInfo attachment(VkImageView view, VkImageLayout layout, VkAttachmentLoadOp load, VkAttachmentStoreOp store,
                                     VkClearValue clear = {}) {
    VkRenderingAttachmentInfo a{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
    a.imageView = view;
    a.imageLayout = layout;
    a.loadOp = load;
    a.storeOp = store;
    a.clearValue = clear;
    return a;
}

VkRenderingInfo rendering_info(VkExtent2D extent, const VkRenderingAttachmentInfo* colour, const VkRenderingAttachmentInfo* depth,
                               std::uint32_t view_mask = 0) {
    VkRenderingInfo info{VK_STRUCTURE_TYPE_RENDERING_INFO};
    info.renderArea = {{0, 0}, extent};
    info.layerCount = 1;
    info.viewMask = view_mask;
    info.colorAttachmentCount = colour ? 1u : 0u;
    info.pColorAttachments = colour;
    info.pDepthAttachment = depth;
    return info;
}

} // namespace

void StereoRenderer::record(Frame& frame, const DrawList& list, const std::vector<Draw>& draws, const CompositeTarget& target) {
    if (frame.timestamps) {
        vkCmdResetQueryPool(frame.cmd, frame.timestamps, 0, 4);
        vkCmdWriteTimestamp2(frame.cmd, VK_PIPELINE_STAGE_2_TOP_OF_PIPE_BIT, frame.timestamps, 0);
    }
    record_shadow_pass(frame, draws);
    write_timestamp(frame.cmd, frame.timestamps, 1);
    record_eye_passes(frame, list, draws, target.with_eyes);
    write_timestamp(frame.cmd, frame.timestamps, 2);
    const VkImageLayout eyes_layout = record_composite(frame, target);
    // The interface over the window's image (its own render pass: Dear ImGui's Vulkan backend wants one).
    if (ui_ && target.present) ui_->record(frame.cmd, target.view, target.extent);
    write_timestamp(frame.cmd, frame.timestamps, 3);
    if (frame.timestamps) frame.timestamps_written = true;
    record_hand_over(frame, target, eyes_layout);
}

// Each batch's instances from its offset in the frame's instance buffer. Closed meshes cull their
// back faces; sheets (petals, leaves) are drawn from both sides.
void StereoRenderer::draw_batches(const Frame& frame, const std::vector<Draw>& draws, bool shadow_casters_only, bool translucent, Shading shading) const {
    // The shadow pass needs positions only: no materials.
    const bool materials = !shadow_casters_only;
    std::uint32_t first = 0;
    VkDescriptorSet bound = VK_NULL_HANDLE;
    for (const auto& d : draws) {
        if ((!shadow_casters_only || d.casts_shadow) && d.translucent == translucent) {
            const VkBuffer buffers[2] = {d.mesh->vertices.buffer, frame.instances.buffer};
            const VkDeviceSize offsets[2] = {0, first * sizeof(MeshInstance)};
            vkCmdBindVertexBuffers(frame.cmd, 0, 2, buffers, offsets);
            vkCmdBindIndexBuffer(frame.cmd, d.mesh->indices.buffer, 0, VK_INDEX_TYPE_UINT32);
            vkCmdSetCullMode(frame.cmd, d.mesh->closed ? VK_CULL_MODE_BACK_BIT : VK_CULL_MODE_NONE);
            for (const auto& part : d.mesh->parts) {
                if (shading != Shading::any && part.shading != shading) continue;
                if (materials) {
                    if (part.material != bound) {
                        vkCmdBindDescriptorSets(frame.cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, scene_pipeline_layout_, 1, 1, &part.material, 0, nullptr);
                        bound = part.material;
                    }
                    // Past the eye (offset 0, pushed per pass): the material's factors.
                    constexpr auto after_eye = static_cast<std::uint32_t>(sizeof(std::int32_t));
                    vkCmdPushConstants(frame.cmd, scene_pipeline_layout_, VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, after_eye,
                                       static_cast<std::uint32_t>(sizeof(SceneConstants)) - after_eye,
                                       reinterpret_cast<const char*>(&part.constants) + after_eye);
                }
                vkCmdDrawIndexed(frame.cmd, part.index_count, d.instances, part.first_index, 0, 0);
            }
        }
        first += d.instances;
    }
}

// 1. The shadow map: depth from the light, of the batches that cast a shadow.
void StereoRenderer::record_shadow_pass(const Frame& frame, const std::vector<Draw>& draws) const {
    VkCommandBuffer cmd = frame.cmd;
    transition(cmd, shadow_.image, VK_IMAGE_ASPECT_DEPTH_BIT, 1, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL,
               VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, 0, VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT,
               VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT);
    const auto depth = attachment(shadow_.view, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL, VK_ATTACHMENT_LOAD_OP_CLEAR, VK_ATTACHMENT_STORE_OP_STORE,
                                  far_depth());
    const auto pass = rendering_info(shadow_.extent, nullptr, &depth);
    vkCmdBeginRendering(cmd, &pass);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, shadow_pipeline_);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, scene_pipeline_layout_, 0, 1, &frame.scene_set, 0, nullptr);
    const std::int32_t no_eye = 0;
    vkCmdPushConstants(cmd, scene_pipeline_layout_, VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof no_eye, &no_eye);
    set_viewport(cmd, shadow_.extent);
    draw_batches(frame, draws, true, false);
    vkCmdEndRendering(cmd);
    transition(cmd, shadow_.image, VK_IMAGE_ASPECT_DEPTH_BIT, 1, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
               VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT, VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT,
               VK_ACCESS_2_SHADER_SAMPLED_READ_BIT);
}

// Both depth layers cleared once, whether the eyes are drawn in one pass or two.
void StereoRenderer::clear_eye_depth(VkCommandBuffer cmd) const {
    transition(cmd, depth_.image, VK_IMAGE_ASPECT_DEPTH_BIT, 2, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
               VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT, 0, VK_PIPELINE_STAGE_2_CLEAR_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT);
    const VkClearDepthStencilValue far_plane{1.0f, 0};
    const VkImageSubresourceRange both_layers{VK_IMAGE_ASPECT_DEPTH_BIT, 0, 1, 0, 2};
    vkCmdClearDepthStencilImage(cmd, depth_.image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &far_plane, 1, &both_layers);
    transition(cmd, depth_.image, VK_IMAGE_ASPECT_DEPTH_BIT, 2, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL,
               VK_PIPELINE_STAGE_2_CLEAR_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
               VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT,
               VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT);
}

// 2. Both eyes into the two-layer image: one multiview pass (viewMask 0b11: gl_ViewIndex picks the
// eye), or a pass per eye's layer (a push constant gives the eye).
void StereoRenderer::record_eye_passes(const Frame& frame, const DrawList& list, const std::vector<Draw>& draws, bool both_eyes_wanted) const {
    VkCommandBuffer cmd = frame.cmd;
    transition(cmd, eyes_.image, VK_IMAGE_ASPECT_COLOR_BIT, 2, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, none, 0,
               VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT);
    const bool msaa = eyes_msaa_.image != VK_NULL_HANDLE;
    if (msaa) {
        // After the last frame's passes and resolve read it (two frames may be in flight).
        transition(cmd, eyes_msaa_.image, VK_IMAGE_ASPECT_COLOR_BIT, 2, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                   VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT | VK_PIPELINE_STAGE_2_RESOLVE_BIT, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT,
                   VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT);
    }
    clear_eye_depth(cmd);
    VkClearValue background{};
    background.color = {{list.background.r, list.background.g, list.background.b, 1.0f}};
    // Mono shows the left layer only: its second pass (the right eye, at the same place) was half the
    // eyes' time on lavapipe for nothing. Both still when the eyes themselves are read back.
    const int passes = multiview_ || (options_.mode == StereoMode::mono && !both_eyes_wanted) ? 1 : 2;
    for (int pass = 0; pass < passes; ++pass) {
        VkImageView single = multiview_ ? eyes_.view : eye_layer_[pass];
        auto colour = attachment(single, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_ATTACHMENT_LOAD_OP_CLEAR, VK_ATTACHMENT_STORE_OP_STORE, background);
        if (msaa) {
            // Drawn with several samples a pixel, then averaged into the eye's image: by the multiview
            // pass as it ends; after the passes one per eye (lavapipe's resolve at the end of a pass
            // into the second layer left it unwritten).
            colour.imageView = multiview_ ? eyes_msaa_.view : eye_msaa_layer_[pass];
            if (multiview_) {
                colour.storeOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
                colour.resolveMode = VK_RESOLVE_MODE_AVERAGE_BIT;
                colour.resolveImageView = single;
                colour.resolveImageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
            }
        }
        const auto depth = attachment(multiview_ ? depth_.view : depth_layer_[pass], VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL, VK_ATTACHMENT_LOAD_OP_LOAD,
                                      VK_ATTACHMENT_STORE_OP_DONT_CARE, far_depth());
        const auto scene = rendering_info(eyes_.extent, &colour, &depth, multiview_ ? 0b11u : 0u);
        vkCmdBeginRendering(cmd, &scene);
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, multiview_ ? scene_pipeline_ : per_eye_pipeline_);
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, scene_pipeline_layout_, 0, 1, &frame.scene_set, 0, nullptr);
        const std::int32_t base = pass;
        vkCmdPushConstants(cmd, scene_pipeline_layout_, VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof base, &base);
        set_viewport(cmd, eyes_.extent);
        draw_batches(frame, draws, false, false, Shading::plain);
        // Then the parts with materials of their own, and the alpha-masked ones, each with its variant.
        const std::pair<Shading, VkPipeline> variants[2] = {{Shading::material, multiview_ ? material_pipeline_ : per_eye_material_pipeline_},
                                                            {Shading::masked, multiview_ ? masked_pipeline_ : per_eye_masked_pipeline_}};
        for (const auto& variant : variants) {
            const Shading shading = variant.first; // a plain name: clang cannot capture a structured binding
            const auto has = [shading](const Draw& d) {
                return !d.translucent && std::any_of(d.mesh->parts.begin(), d.mesh->parts.end(), [shading](const Part& p) { return p.shading == shading; });
            };
            if (std::none_of(draws.begin(), draws.end(), has)) continue;
            vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, variant.second);
            draw_batches(frame, draws, false, false, shading);
        }
        if (std::any_of(draws.begin(), draws.end(), [](const Draw& d) { return d.translucent; })) {
            vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, multiview_ ? translucent_pipeline_ : per_eye_translucent_pipeline_);
            draw_batches(frame, draws, false, true);
        }
        vkCmdEndRendering(cmd);
    }
    if (msaa && !multiview_) {
        transition(cmd, eyes_msaa_.image, VK_IMAGE_ASPECT_COLOR_BIT, 2, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                   VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT, VK_PIPELINE_STAGE_2_RESOLVE_BIT,
                   VK_ACCESS_2_TRANSFER_READ_BIT);
        transition(cmd, eyes_.image, VK_IMAGE_ASPECT_COLOR_BIT, 2, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                   VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT, VK_PIPELINE_STAGE_2_RESOLVE_BIT,
                   VK_ACCESS_2_TRANSFER_WRITE_BIT);
        const VkImageSubresourceLayers both{VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, static_cast<std::uint32_t>(passes)};
        const VkImageResolve region{both, {0, 0, 0}, both, {0, 0, 0}, {eyes_.extent.width, eyes_.extent.height, 1}};
        vkCmdResolveImage(cmd, eyes_msaa_.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, eyes_.image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region);
        transition(cmd, eyes_.image, VK_IMAGE_ASPECT_COLOR_BIT, 2, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                   VK_PIPELINE_STAGE_2_RESOLVE_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, VK_ACCESS_2_SHADER_SAMPLED_READ_BIT);
        return;
    }
    transition(cmd, eyes_.image, VK_IMAGE_ASPECT_COLOR_BIT, 2, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
               VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT,
               VK_ACCESS_2_SHADER_SAMPLED_READ_BIT);
}

// 3. Composite to the display's format, into the offscreen output or the window's image. Side by
// side and mono are plain copies of the eyes (on lavapipe far cheaper than a full-screen fragment
// pass) when the target takes transfers; interleaved rows and anaglyph need the composite shader.
// The heads-up panels go on top. Returns the eyes' layout after it.
VkImageLayout StereoRenderer::record_composite(const Frame& frame, const CompositeTarget& target) const {
    VkCommandBuffer cmd = frame.cmd;
    const bool blit = target.blit && (options_.mode == StereoMode::side_by_side || options_.mode == StereoMode::mono);
    if (blit) {
        copy_eyes_to_target(cmd, target);
    } else {
        transition(cmd, target.image, VK_IMAGE_ASPECT_COLOR_BIT, 1, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                   VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, 0, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
                   VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT);
    }
    const auto out = attachment(target.view, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, blit ? VK_ATTACHMENT_LOAD_OP_LOAD : VK_ATTACHMENT_LOAD_OP_DONT_CARE,
                                VK_ATTACHMENT_STORE_OP_STORE);
    const auto composite = rendering_info(target.extent, &out, nullptr);
    vkCmdBeginRendering(cmd, &composite);
    set_viewport(cmd, target.extent);
    if (blit) clear_columns(cmd, target);
    else draw_composite(cmd, target);
    if (!frame.overlay_ranges.empty() && target.overlay_pipeline) draw_overlay(frame, target);
    vkCmdEndRendering(cmd);
    return blit ? VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL : VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
}

// Side by side (both layers next to each other) or mono (the left layer) into the target: a plain
// copy when the formats match (on lavapipe a memcpy, where a blit runs a shader), else a blit.
void StereoRenderer::copy_eyes_to_target(VkCommandBuffer cmd, const CompositeTarget& target) const {
    // After the eyes' passes, or after their resolve (whose barrier ends at the fragment shader): both
    // are in this barrier's first scope, so it waits for either. A copy is not a blit: all transfers.
    transition(cmd, eyes_.image, VK_IMAGE_ASPECT_COLOR_BIT, 2, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
               VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT | VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_2_RESOLVE_BIT,
               VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_READ_BIT);
    transition(cmd, target.image, VK_IMAGE_ASPECT_COLOR_BIT, 1, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
               VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, 0, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT);
    const auto w = static_cast<std::int32_t>(eyes_.extent.width), h = static_cast<std::int32_t>(eyes_.extent.height);
    const auto area = static_cast<std::int32_t>(options_.eye_width + options_.column_px);
    const std::uint32_t count = options_.mode == StereoMode::side_by_side ? 2u : 1u;
    VkImageBlit blits[2] = {};
    VkImageCopy copies[2] = {};
    for (std::uint32_t e = 0; e < count; ++e) {
        const auto x = static_cast<std::int32_t>(e) * area;
        const VkImageSubresourceLayers layer{VK_IMAGE_ASPECT_COLOR_BIT, 0, e, 1}, output{VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
        blits[e] = {layer, {{0, 0, 0}, {w, h, 1}}, output, {{x, 0, 0}, {x + w, h, 1}}};
        copies[e] = {layer, {0, 0, 0}, output, {x, 0, 0}, {eyes_.extent.width, eyes_.extent.height, 1}};
    }
    if (target.format == options_.colour_format) {
        vkCmdCopyImage(cmd, eyes_.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, target.image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, count, copies);
    } else {
        vkCmdBlitImage(cmd, eyes_.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, target.image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, count, blits,
                       VK_FILTER_NEAREST);
    }
    transition(cmd, target.image, VK_IMAGE_ASPECT_COLOR_BIT, 1, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
               VK_PIPELINE_STAGE_2_BLIT_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
               VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT);
}

// The columns beside the copied eyes (the composite shader fills them itself).
void StereoRenderer::clear_columns(VkCommandBuffer cmd, const CompositeTarget& target) const {
    if (options_.column_px == 0) return;
    const std::uint32_t area = options_.eye_width + options_.column_px;
    VkClearAttachment clear{VK_IMAGE_ASPECT_COLOR_BIT, 0, {}};
    for (int k = 0; k < 4; ++k) clear.clearValue.color.float32[k] = detail::column_colour[k];
    VkClearRect rects[2] = {};
    const std::uint32_t count = options_.mode == StereoMode::side_by_side ? 2u : 1u;
    for (std::uint32_t e = 0; e < count; ++e) {
        const std::uint32_t x = e * area + options_.eye_width;
        const std::uint32_t width = x < target.extent.width ? std::min(options_.column_px, target.extent.width - x) : 0u;
        rects[e] = {{{static_cast<std::int32_t>(x), 0}, {std::max(1u, width), target.extent.height}}, 0, 1};
        if (width == 0) return;
    }
    vkCmdClearAttachments(cmd, 1, &clear, count, rects);
}

// Any mode through the composite shader: one full-screen triangle sampling both layers.
void StereoRenderer::draw_composite(VkCommandBuffer cmd, const CompositeTarget& target) const {
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, target.pipeline);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, composite_pipeline_layout_, 0, 1, &composite_set_, 0, nullptr);
    CompositeConstants constants{static_cast<std::int32_t>(options_.mode), static_cast<std::int32_t>(options_.eye_width),
                                 static_cast<std::int32_t>(options_.eye_height), 0, static_cast<std::int32_t>(options_.eye_width + options_.column_px), {0, 0, 0}, {}};
    for (int k = 0; k < 4; ++k) constants.column_colour[k] = detail::column_colour[k];
    vkCmdPushConstants(cmd, composite_pipeline_layout_, VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof constants, &constants);
    vkCmdDraw(cmd, 3, 1, 0, 0);
}

// The heads-up panels, once per eye's area in side by side (at screen depth for both eyes), once
// otherwise.
void StereoRenderer::draw_overlay(const Frame& frame, const CompositeTarget& target) const {
    VkCommandBuffer cmd = frame.cmd;
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, target.overlay_pipeline);
    const VkDeviceSize zero = 0;
    vkCmdBindVertexBuffers(cmd, 0, 1, &frame.overlay.buffer, &zero);
    const int areas = options_.mode == StereoMode::side_by_side ? 2 : 1;
    for (int area = 0; area < areas; ++area) {
        // Each eye's panels stay in that eye's half: a long line must not spill into the other eye.
        // And in its scene: never over the column kept for panels.
        const std::uint32_t area_width = options_.eye_width + options_.column_px;
        const std::uint32_t left = static_cast<std::uint32_t>(area) * area_width;
        const VkRect2D scissor{{static_cast<std::int32_t>(left), 0},
                               {left < target.extent.width ? std::min(options_.eye_width, target.extent.width - left) : 1u, target.extent.height}};
        vkCmdSetScissor(cmd, 0, 1, &scissor);
        for (std::size_t k = 0; k < overlay_.size() && k < frame.overlay_ranges.size() && k < frame.overlay_origins.size(); ++k) {
            const auto [first, count] = frame.overlay_ranges[k];
            const auto& origin = frame.overlay_origins[k][static_cast<std::size_t>(area)];
            if (count == 0 || !origin) continue;
            const OverlayConstants c{static_cast<float>(target.extent.width), static_cast<float>(target.extent.height),
                                     origin->x + static_cast<float>(area) * static_cast<float>(area_width), origin->y, overlay_[k].scale};
            vkCmdPushConstants(cmd, overlay_layout_, VK_SHADER_STAGE_VERTEX_BIT, 0, sizeof c, &c);
            vkCmdDraw(cmd, count, 1, first, 0);
        }
    }
}

// 4. Read back (offscreen, or a screenshot of the window), hand the window its image, copy the eyes
// out when asked, and make the copies visible to the host.
void StereoRenderer::record_hand_over(const Frame& frame, const CompositeTarget& target, VkImageLayout eyes_layout) const {
    VkCommandBuffer cmd = frame.cmd;
    VkImageLayout layout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    if (target.read_back) {
        transition(cmd, target.image, VK_IMAGE_ASPECT_COLOR_BIT, 1, layout, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                   VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT, VK_PIPELINE_STAGE_2_COPY_BIT,
                   VK_ACCESS_2_TRANSFER_READ_BIT);
        layout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
        VkBufferImageCopy region{};
        region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
        region.imageExtent = {target.extent.width, target.extent.height, 1};
        vkCmdCopyImageToBuffer(cmd, target.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, frame.readback.buffer, 1, &region);
    }
    if (target.present) {
        transition(cmd, target.image, VK_IMAGE_ASPECT_COLOR_BIT, 1, layout, VK_IMAGE_LAYOUT_PRESENT_SRC_KHR,
                   VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT | VK_PIPELINE_STAGE_2_COPY_BIT,
                   VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_2_TRANSFER_READ_BIT, VK_PIPELINE_STAGE_2_NONE, 0);
    }
    if (target.with_eyes) copy_eyes_to_host(frame, target, eyes_layout);
    const VkMemoryBarrier2 host{VK_STRUCTURE_TYPE_MEMORY_BARRIER_2, nullptr, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                                VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT};
    VkDependencyInfo dep{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
    dep.memoryBarrierCount = 1;
    dep.pMemoryBarriers = &host;
    vkCmdPipelineBarrier2(cmd, &dep);
}

// Both eyes' layers into the readback buffer after the composed image.
void StereoRenderer::copy_eyes_to_host(const Frame& frame, const CompositeTarget& target, VkImageLayout eyes_layout) const {
    if (eyes_layout != VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL) {
        transition(frame.cmd, eyes_.image, VK_IMAGE_ASPECT_COLOR_BIT, 2, eyes_layout, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                   VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, VK_ACCESS_2_SHADER_SAMPLED_READ_BIT, VK_PIPELINE_STAGE_2_COPY_BIT,
                   VK_ACCESS_2_TRANSFER_READ_BIT);
    }
    VkBufferImageCopy eyes[2] = {};
    for (std::uint32_t e = 0; e < 2; ++e) {
        eyes[e].bufferOffset = 4ull * target.extent.width * target.extent.height + e * 4ull * eyes_.extent.width * eyes_.extent.height;
        eyes[e].imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, e, 1};
        eyes[e].imageExtent = {eyes_.extent.width, eyes_.extent.height, 1};
    }
    vkCmdCopyImageToBuffer(frame.cmd, eyes_.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, frame.readback.buffer, 2, eyes);
}

} // namespace ikebana::render
