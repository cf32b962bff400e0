#version 450 core
// Counts the metric's images from the raster path's RGBA8 picture: red I1, green I2,
// blue I3 (no depth bit).
layout(binding = 0, rgba8) uniform readonly image2D u_image;
uint bitsAt(ivec2 p) {
    vec4 c = imageLoad(u_image, p);
    return (c.r > 0.5 ? 1u : 0u) | (c.g > 0.5 ? 2u : 0u) | (c.b > 0.5 ? 4u : 0u);
}
#include "include/metric_counts.glsl"
