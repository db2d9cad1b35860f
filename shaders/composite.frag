#version 450
// The two eyes (layers 0 and 1 of the multiview image) to the output the display wants.
layout(set = 0, binding = 0) uniform sampler2DArray eyes;
layout(push_constant) uniform Composite {
    int mode;        // 0 side by side, 1 row-interleaved (polarized), 2 anaglyph red-cyan, 3 mono
    int eye_width;
    int eye_height;
    int first_row_eye; // rows: which eye the output's row 0 carries (depends on the display)
    int area_width;    // the eye's image and, right of it, the column a window keeps for its panels
    int padding[3];
    vec4 column_colour;
} c;
layout(location = 0) out vec4 out_colour;

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    // Side by side, each half is an eye's area; otherwise one area both eyes share.
    int area = c.mode == 0 && p.x >= c.area_width ? 1 : 0;
    p.x -= area * c.area_width;
    if (p.x >= c.eye_width) {
        out_colour = c.column_colour;
    } else if (c.mode == 0) {
        out_colour = texelFetch(eyes, ivec3(p, area), 0);
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
