#version 450 core
// The viewer's compute rasteriser without subgroup operations (any GL 4.5 context); the
// body is include/viewer_points_splat.glsl.
#include "include/viewer_points_splat.glsl"
