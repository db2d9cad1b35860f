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

// 2x2 percentage-closer filtering: soft enough edges at 2048 texels over the scene.
float lit_fraction() {
    vec3 p = in_light_space.xyz / in_light_space.w;
    vec2 uv = p.xy * 0.5 + 0.5;
    if (uv.x < 0.0 || uv.x > 1.0 || uv.y < 0.0 || uv.y > 1.0 || p.z > 1.0) return 1.0;
    vec2 texel = 1.0 / vec2(textureSize(shadow_map, 0));
    float sum = 0.0;
    for (int i = 0; i < 2; ++i) {
        for (int j = 0; j < 2; ++j) {
            sum += texture(shadow_map, vec3(uv + (vec2(i, j) - 0.5) * texel, p.z - 0.002));
        }
    }
    return sum * 0.25;
}

void main() {
    vec3 n = normalize(in_normal);
    float facing = dot(n, -normalize(frame.light_direction.xyz));
    // Thin parts (petals, leaves) are lit from either side.
    float diffuse = abs(facing);
    out_colour = vec4(in_colour.rgb * (0.3 + 0.7 * diffuse * lit_fraction()), 1.0);
}
