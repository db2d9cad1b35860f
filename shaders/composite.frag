#version 450
// The two eyes (layers 0 and 1 of the multiview image) to the output the display wants.
layout(set = 0, binding = 0) uniform sampler2DArray eyes;
layout(push_constant) uniform Composite {
    int mode;        // 0 side by side, 1 row-interleaved (polarized), 2 anaglyph red-cyan, 3 mono
    int eye_width;
    int eye_height;
    int first_row_eye; // rows: which eye the output's row 0 carries (depends on the display)
} c;
layout(location = 0) out vec4 out_colour;

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    if (c.mode == 0) {
        int eye = p.x >= c.eye_width ? 1 : 0;
        out_colour = texelFetch(eyes, ivec3(p.x - eye * c.eye_width, p.y, eye), 0);
    } else if (c.mode == 1) {
        int eye = (p.y + c.first_row_eye) & 1;
        out_colour = texelFetch(eyes, ivec3(p, eye), 0);
    } else if (c.mode == 2) {
        vec3 l = texelFetch(eyes, ivec3(p, 0), 0).rgb;
        vec3 r = texelFetch(eyes, ivec3(p, 1), 0).rgb;
        out_colour = vec4(l.r, r.g, r.b, 1.0);
    } else {
        out_colour = texelFetch(eyes, ivec3(p, 0), 0);
    }
}
