#version 450 core
// Copies the compute rasteriser's result (viewer_points_splat.comp) into an eye target's
// colour and depth, so eye-dome lighting and everything drawn after see what GL_POINTS
// would have left there. Pixels no point reached keep the target's clear values.
layout(binding = 0, r32ui) uniform readonly uimage2D u_depth_bits;
layout(binding = 1, r32ui) uniform readonly uimage2D u_colour_bits;
out vec4 o_colour;
void main() {
    ivec2 px = ivec2(gl_FragCoord.xy);
    uint d = imageLoad(u_depth_bits, px).r;
    if (d == 0xFFFFFFFFu) discard;
    o_colour = unpackUnorm4x8(imageLoad(u_colour_bits, px).r);
    gl_FragDepth = uintBitsToFloat(d);
}
