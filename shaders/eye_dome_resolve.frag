#version 450 core
// Eye-dome lighting: darkens a point by how much nearer its 8 neighbours are, in log
// depth; pixels with no point get the background colour.
#include "include/linear_depth.glsl"
uniform sampler2D u_colour;
uniform sampler2D u_depth;
uniform vec4 u_viewport;       // x, y, w, h of the output
uniform int u_edl;
uniform float u_strength;
uniform float u_near;
uniform float u_far;
uniform vec3 u_background;
out vec4 o_colour;
void main() {
    ivec2 size = textureSize(u_colour, 0);
    ivec2 px = clamp(ivec2((gl_FragCoord.xy - u_viewport.xy) / u_viewport.zw * vec2(size)), ivec2(0), size - 1);
    float d = texelFetch(u_depth, px, 0).r;
    if (d >= 1.0) { o_colour = vec4(u_background, 1.0); return; }
    vec3 c = texelFetch(u_colour, px, 0).rgb;
    if (u_edl != 0) {
        float ld = log2(linearDepth(d, u_near, u_far));
        const ivec2 offsets[8] = ivec2[](ivec2(1, 0), ivec2(-1, 0), ivec2(0, 1), ivec2(0, -1),
                                         ivec2(1, 1), ivec2(-1, -1), ivec2(1, -1), ivec2(-1, 1));
        float sum = 0.0;
        for (int i = 0; i < 8; ++i) {
            ivec2 q = clamp(px + offsets[i], ivec2(0), size - 1);
            float dn = texelFetch(u_depth, q, 0).r;
            if (dn < 1.0) sum += max(0.0, ld - log2(linearDepth(dn, u_near, u_far)));
        }
        c *= exp(-sum / 8.0 * 300.0 * u_strength);
    }
    o_colour = vec4(c, 1.0);
}
