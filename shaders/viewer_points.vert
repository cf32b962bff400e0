#version 450 core
// The viewer's points (viewer::PointRenderer): camera-relative chunks, coloured by the
// file, by height (the jet table), white, by ground-truth label, or by height above ground; pixel-sized or
// distance-attenuated; points outside the cutting volume are not drawn.
#include "include/jet.glsl"
layout(location = 0) in vec3 a_position;   // relative to the chunk centre
layout(location = 1) in vec4 a_rgb;        // 0xLLRRGGBB read as BGRA bytes (L = label)
layout(location = 2) in float a_above_ground_m;   // height above the fitted terrain
uniform mat4 u_model_view;                 // computed in double on the CPU
uniform mat4 u_projection;
uniform float u_chunk_z;                   // chunk centre height (local frame)
uniform float u_z_min;
uniform float u_z_max;
uniform int u_colour_mode;                 // 0 file, 1 height jet, 2 white, 3 label, 4 above ground
uniform float u_above_ground_max_m;        // the cloud's highest height above ground
uniform float u_size_px;
uniform int u_attenuate;
uniform float u_cut_radius;                // cutting volume: < 0 off
uniform vec3 u_cut_centre;                 // relative to the chunk centre
out vec4 v_colour;
void main() {
    if (u_cut_radius >= 0.0 && distance(a_position, u_cut_centre) > u_cut_radius) {
        gl_Position = vec4(2.0, 2.0, 2.0, 1.0);   // outside the clip volume: not drawn
        gl_PointSize = 1.0;
        v_colour = vec4(0.0);
        return;
    }
    vec4 p = u_model_view * vec4(a_position, 1.0);
    gl_Position = u_projection * p;
    vec3 colour;
    if (u_colour_mode == 0) {
        colour = a_rgb.rgb;
    } else if (u_colour_mode == 1) {
        colour = jetColour(a_position.z + u_chunk_z, u_z_min, u_z_max);
    } else if (u_colour_mode == 2) {
        colour = vec3(1.0);
    } else if (u_colour_mode == 4) {
        // The file's whitened ground stays white; the rest by height above the terrain, so a
        // target on a hilltop takes the same colour as one in a valley.
        bool white = all(greaterThanEqual(a_rgb.rgb, vec3(1.0)));
        colour = white ? vec3(1.0) : jetColour(a_above_ground_m, 0.0, u_above_ground_max_m);
    } else {
        int label = int(round(a_rgb.a * 255.0));   // 0 ground, 1 environment, 2 target
        colour = label == 2 ? vec3(1.0, 0.0, 0.0) : label == 1 ? vec3(0.6) : vec3(0.3);
    }
    v_colour = vec4(colour, 1.0);
    float size = u_size_px;
    if (u_attenuate != 0) size = u_size_px * 100.0 / max(-p.z, 1e-3);
    gl_PointSize = clamp(size, 1.0, 64.0);
}
