#version 450
layout(location = 0) in vec3 in_normal;
layout(location = 1) in vec4 in_color;
layout(location = 2) in vec4 in_light_space;
layout(location = 0) out vec4 out_color;

layout(set = 0, binding = 0) uniform Eyes {
    mat4 view_projection[2];
    mat4 light_view_projection;
    vec4 light_direction;
} eyes;

void main() {
    // Lambert plus ambient: enough to read shape; shadows come from the shadow pass.
    float diffuse = max(dot(normalize(in_normal), -normalize(eyes.light_direction.xyz)), 0.0);
    out_color = vec4(in_color.rgb * (0.25 + 0.75 * diffuse), in_color.a);
}
