#version 450
#extension GL_GOOGLE_include_directive : require
#include "bend.glsl"
// Depth from the light for the shadow map; the scene pass samples it.
layout(location = 0) in vec3 in_position;
layout(location = 2) in vec4 in_model0;
layout(location = 3) in vec4 in_model1;
layout(location = 4) in vec4 in_model2;
layout(location = 5) in vec4 in_model3;
layout(location = 9) in float in_bend;

layout(set = 0, binding = 0) uniform Frame {
    mat4 view_projection[2];
    mat4 light_view_projection;
    vec4 light_direction;
    vec4 eye_position[2];
} frame;

void main() {
    mat4 model = mat4(in_model0, in_model1, in_model2, in_model3);
    gl_Position = frame.light_view_projection * model * vec4(bent_position(in_position, in_bend), 1.0);
}
