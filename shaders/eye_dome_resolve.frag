#version 450 core
// Eye-dome lighting: darkens a point by how much nearer its 8 neighbours are, in log
// depth; pixels with no point get the background colour. The points come from the eye
// target's colour and depth (GL_POINTS) or from the compute rasteriser's images (its depth
// bits, all ones where no point landed, and packed colours).
#include "include/linear_depth.glsl"
uniform sampler2D u_colour;
uniform sampler2D u_depth;
layout(binding = 0, r32ui) uniform readonly uimage2D u_depth_bits;
layout(binding = 1, r32ui) uniform readonly uimage2D u_colour_bits;
uniform int u_from_images;     // 1: read the compute rasteriser's images
uniform ivec2 u_size;          // the eye target, pixels
uniform vec4 u_viewport;       // x, y, w, h of the output
uniform int u_edl;
uniform float u_strength;
uniform float u_near;
uniform float u_far;
uniform vec3 u_background;
out vec4 o_colour;
float depthAt(ivec2 p) {
    if (u_from_images == 0) return texelFetch(u_depth, p, 0).r;
    uint bits = imageLoad(u_depth_bits, p).r;
    return bits == 0xFFFFFFFFu ? 1.0 : uintBitsToFloat(bits);
}
void main() {
    ivec2 size = u_size;
    ivec2 px = clamp(ivec2((gl_FragCoord.xy - u_viewport.xy) / u_viewport.zw * vec2(size)), ivec2(0), size - 1);
    float d = depthAt(px);
    if (d >= 1.0) { o_colour = vec4(u_background, 1.0); return; }
    vec3 c = u_from_images == 0 ? texelFetch(u_colour, px, 0).rgb : unpackUnorm4x8(imageLoad(u_colour_bits, px).r).rgb;
    if (u_edl != 0) {
        float ld = log2(linearDepth(d, u_near, u_far));
        const ivec2 offsets[8] = ivec2[](ivec2(1, 0), ivec2(-1, 0), ivec2(0, 1), ivec2(0, -1),
                                         ivec2(1, 1), ivec2(-1, -1), ivec2(1, -1), ivec2(-1, 1));
        float sum = 0.0;
        for (int i = 0; i < 8; ++i) {
            ivec2 q = clamp(px + offsets[i], ivec2(0), size - 1);
            float dn = depthAt(q);
            if (dn < 1.0) sum += max(0.0, ld - log2(linearDepth(dn, u_near, u_far)));
        }
        c *= exp(-sum / 8.0 * 300.0 * u_strength);
    }
    o_colour = vec4(c, 1.0);
}
