#version 450
layout(location = 0) in vec3 in_normal;
layout(location = 1) in vec4 in_colour;
layout(location = 2) in vec4 in_light_space;
layout(location = 0) out vec4 out_colour;

layout(set = 0, binding = 0) uniform Frame {
    mat4 view_projection[2];
    mat4 light_view_projection;
    vec4 light_direction;
} frame;
layout(set = 0, binding = 1) uniform sampler2DShadow shadow_map;

// One comparison tap: the sampler's linear filter blends the four nearest comparisons (hardware
// percentage-closer filtering), as soft as four taps at a quarter of the fragment work.
float lit_fraction() {
    vec3 p = in_light_space.xyz / in_light_space.w;
    vec2 uv = p.xy * 0.5 + 0.5;
    if (uv.x < 0.0 || uv.x > 1.0 || uv.y < 0.0 || uv.y > 1.0 || p.z > 1.0) return 1.0;
    return texture(shadow_map, vec3(uv, p.z - 0.002));
}

void main() {
    vec3 n = normalize(in_normal);
    float facing = dot(n, -normalize(frame.light_direction.xyz));
    // Thin parts (petals, leaves) are lit from either side.
    float diffuse = abs(facing);
    out_colour = vec4(in_colour.rgb * (0.3 + 0.7 * diffuse * lit_fraction()), in_colour.a);
}
