#version 450 core
// Counts the metric's images from the compute splats' r32ui bit mask.
layout(binding = 0, r32ui) uniform readonly uimage2D u_image;
uint bitsAt(ivec2 p) { return imageLoad(u_image, p).r; }
#include "include/metric_counts.glsl"
