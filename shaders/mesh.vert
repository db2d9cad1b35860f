#version 450
#extension GL_EXT_multiview : require
#extension GL_GOOGLE_include_directive : require
#include "bend.glsl"
// Scene geometry for both eyes in one pass: gl_ViewIndex picks the eye's off-axis projection.
// Everything is instanced: pins, stem segments and petals are one mesh each with many instances.
layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in vec4 in_model0;
layout(location = 3) in vec4 in_model1;
layout(location = 4) in vec4 in_model2;
layout(location = 5) in vec4 in_model3;
layout(location = 6) in vec4 in_colour;
layout(location = 7) in vec2 in_uv;
layout(location = 8) in vec4 in_tangent;
layout(location = 9) in float in_bend;

layout(set = 0, binding = 0) uniform Frame {
    mat4 view_projection[2];
    mat4 light_view_projection;
    vec4 light_direction;
    vec4 eye_position[2];
} frame;

// base: 0 in the multiview pass (gl_ViewIndex picks the eye); the eye itself when each eye has its
// own pass. The rest is the material's (mesh.frag).
layout(push_constant) uniform Constants {
    int base;
} eye;

layout(location = 0) out vec3 out_normal;
layout(location = 1) out vec4 out_colour;
layout(location = 2) out vec4 out_light_space;
#ifdef MATERIAL // mesh_material.vert.spv: what a glTF material's shading needs (mesh.frag)
layout(location = 3) out vec2 out_uv;
layout(location = 4) out vec4 out_tangent;
layout(location = 5) out vec3 out_to_eye;
#endif

void main() {
    mat4 model = mat4(in_model0, in_model1, in_model2, in_model3);
    vec3 position = in_position, normal = in_normal, tangent = in_tangent.xyz;
    if (in_bend != 0.0) { // a cupped petal; the pins and stems by the hundred are not bent
        position = bent_position(in_position, in_bend);
        normal = bent_direction(in_normal, in_bend, in_position.x);
        tangent = bent_direction(in_tangent.xyz, in_bend, in_position.x);
    }
    vec4 world = model * vec4(position, 1.0);
    // Scaled instances (pins, stem segments): the inverse transpose keeps normals perpendicular.
    out_normal = transpose(inverse(mat3(model))) * normal;
    out_colour = in_colour;
    out_light_space = frame.light_view_projection * world;
#ifdef MATERIAL
    out_tangent = vec4(mat3(model) * tangent, in_tangent.w);
    out_uv = in_uv;
    out_to_eye = frame.eye_position[gl_ViewIndex + eye.base].xyz - world.xyz;
#endif
    gl_Position = frame.view_projection[gl_ViewIndex + eye.base] * world;
}
