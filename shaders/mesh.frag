#version 450
// The scene's fragments, compiled three ways (shaders/CMakeLists.txt): plain (mesh.frag.spv: the
// built-in shapes and parts without a material of their own, lit by their instance's colour), with
// MATERIAL (a glTF material: its factors, pictures, normal map and highlight) and with ALPHA_MASK as
// well (a leaf cut out of a quad). On lavapipe every value passed from the vertices is interpolated at
// every fragment, and a shader that may discard cannot test depth before it runs: the plain variant
// keeps the pins and stems by the hundred at what they cost before materials existed.
layout(location = 0) in vec3 in_normal;
layout(location = 1) in vec4 in_colour;
layout(location = 2) in vec4 in_light_space;
#ifdef MATERIAL
layout(location = 3) in vec2 in_uv;
layout(location = 4) in vec4 in_tangent;
layout(location = 5) in vec3 in_to_eye;
#endif
layout(location = 0) out vec4 out_colour;

layout(set = 0, binding = 0) uniform Frame {
    mat4 view_projection[2];
    mat4 light_view_projection;
    vec4 light_direction;
    vec4 eye_position[2];
} frame;
layout(set = 0, binding = 1) uniform sampler2DShadow shadow_map;

#ifdef MATERIAL
// The material's pictures (white and a flat normal where it has none).
layout(set = 1, binding = 0) uniform sampler2D base_colour_map;
layout(set = 1, binding = 1) uniform sampler2D normal_map;

layout(push_constant) uniform Constants {
    int eye_base;
    int normal_mapped;
    float alpha_cutoff; // negative: opaque
    float normal_scale;
    vec4 base_colour;
    float metallic;
    float roughness;
    int textured;       // 0: no base colour picture: not sampled
} material;
#endif

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
    vec3 to_light = -normalize(frame.light_direction.xyz);
#ifndef MATERIAL
    // Thin parts (petals, leaves) are lit from either side.
    float diffuse = abs(dot(n, to_light));
    out_colour = vec4(in_colour.rgb * (0.3 + 0.7 * diffuse * lit_fraction()), in_colour.a);
#else
    vec4 base = in_colour * material.base_colour;
    if (material.textured != 0) base *= texture(base_colour_map, in_uv);
#ifdef ALPHA_MASK
    // What the picture leaves transparent is not there.
    if (base.a < material.alpha_cutoff) discard;
#endif
    if (material.normal_mapped != 0) {
        vec3 t = normalize(in_tangent.xyz - n * dot(n, in_tangent.xyz));
        vec3 b = cross(n, t) * in_tangent.w;
        vec3 m = texture(normal_map, in_uv).xyz * 2.0 - 1.0;
        m.xy *= material.normal_scale;
        n = normalize(mat3(t, b, n) * m);
    }
    float shade = abs(dot(n, to_light)) * lit_fraction();
    // Metal has little diffuse colour of its own; what is smooth has a highlight (none at roughness 1).
    vec3 lit = base.rgb * (0.3 + 0.7 * shade * (1.0 - 0.8 * material.metallic));
    float smooth_ = 1.0 - material.roughness;
    if (smooth_ > 0.0) {
        vec3 v = normalize(in_to_eye);
        vec3 nv = dot(n, v) < 0.0 ? -n : n; // the side the eye sees
        vec3 h = normalize(to_light + v);
        float shininess = mix(4.0, 256.0, smooth_ * smooth_);
        vec3 tint = mix(vec3(0.04), base.rgb, material.metallic);
        lit += tint * smooth_ * pow(max(dot(nv, h), 0.0), shininess) * lit_fraction() * (shininess + 8.0) / 32.0;
    }
    out_colour = vec4(lit, in_colour.a);
#endif
}
