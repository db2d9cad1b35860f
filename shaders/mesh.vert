#version 450
#extension GL_EXT_multiview : require
// Scene geometry for both eyes in one pass: gl_ViewIndex picks the eye's off-axis projection.
layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in vec4 in_instance_color;

layout(set = 0, binding = 0) uniform Eyes {
    mat4 view_projection[2];
    mat4 light_view_projection;
    vec4 light_direction;
} eyes;

layout(push_constant) uniform Model {
    mat4 model;
} model;

layout(location = 0) out vec3 out_normal;
layout(location = 1) out vec4 out_color;
layout(location = 2) out vec4 out_light_space;

void main() {
    vec4 world = model.model * vec4(in_position, 1.0);
    out_normal = mat3(model.model) * in_normal;
    out_color = in_instance_color;
    out_light_space = eyes.light_view_projection * world;
    gl_Position = eyes.view_projection[gl_ViewIndex] * world;
}
