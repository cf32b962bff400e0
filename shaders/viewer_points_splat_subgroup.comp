#version 450 core
// The viewer's compute rasteriser with the subgroup reduction before its atomics, for
// contexts with GL_KHR_shader_subgroup (basic, vote and arithmetic in compute); the body
// is include/viewer_points_splat.glsl.
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_vote : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#define LADARVR_SUBGROUP 1
#include "include/viewer_points_splat.glsl"
