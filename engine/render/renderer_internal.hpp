#pragma once
// Private to the renderer's own files (stereo_renderer.cpp, render_passes.cpp, render_pipelines.cpp,
// render_meshes.cpp): what the shaders see and the error macro. Not part of the engine's interface.
#include <cstdint>

#include <glm/glm.hpp>
#include <vulkan/vulkan.h>

#include "engine/render/vulkan_context.hpp"

// A failed Vulkan call returns its error (naming the call) from the enclosing Result function.
#define IKEBANA_VK(call)                                                                                                                  \
    do {                                                                                                                                   \
        if (VkResult vk_result_ = (call); vk_result_ != VK_SUCCESS) return vulkan_error(#call, vk_result_);                               \
    } while (false)

namespace ikebana::render::detail {

constexpr VkFormat depth_format = VK_FORMAT_D32_SFLOAT;

// The scene's uniform buffer (binding 0 of the scene set).
struct FrameUniforms {
    glm::mat4 view_projection[2];
    glm::mat4 light_view_projection;
    glm::vec4 light_direction;
    glm::vec4 eye_position[2]; // world, for highlights
};

// A mesh's vertex (binding 0 of the scene and shadow pipelines; the instances are binding 1).
struct Vertex {
    glm::vec3 position;
    glm::vec3 normal;
    glm::vec2 uv;
    glm::vec4 tangent; // xyz, w the bitangent's sign; zero where no normal map applies
};

// The heads-up panels' push constants (overlay.vert).
struct OverlayConstants {
    float target_width, target_height;
    float offset_x, offset_y;
    float scale;
};

// The composite's push constants (composite.frag).
struct CompositeConstants {
    std::int32_t mode;
    std::int32_t eye_width;
    std::int32_t eye_height;
    std::int32_t first_row_eye;
    std::int32_t area_width; // eye_width plus the column kept for panels (render::ScreenLayout)
    std::int32_t padding[3];
    float column_colour[4];
};
// What a window's panel column shows where no panel is drawn (Dear ImGui's window background).
inline constexpr float column_colour[4] = {0.06f, 0.06f, 0.06f, 1.0f};

} // namespace ikebana::render::detail
