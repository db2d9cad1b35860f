#version 450
// Heads-up text and panels in pixels (stb_easy_font's quads, as triangles).
layout(location = 0) in vec3 in_position;
layout(location = 1) in vec4 in_colour;
layout(push_constant) uniform Overlay {
    vec2 target_size;
    vec2 offset;
    float scale;
} o;
layout(location = 0) out vec4 out_colour;

void main() {
    vec2 p = (in_position.xy * o.scale + o.offset) / o.target_size * 2.0 - 1.0;
    gl_Position = vec4(p, 0.0, 1.0);
    out_colour = in_colour;
}
