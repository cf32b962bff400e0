#version 450 core
// Writes the compute rasteriser's nearest depth (viewer_points_splat.comp) into an eye
// target's depth, 1 where no point landed: the depth an OpenXR depth layer hands to the
// compositor, as GL_POINTS would have left it.
layout(binding = 0, r32ui) uniform readonly uimage2D u_depth_bits;
void main() {
    uint d = imageLoad(u_depth_bits, ivec2(gl_FragCoord.xy)).r;
    gl_FragDepth = d == 0xFFFFFFFFu ? 1.0 : uintBitsToFloat(d);
}
