#version 450 core
// The viewer's points (viewer::PointRenderer): camera-relative chunks, coloured by the
// file, by height (the jet table), white, by ground-truth label, by height above ground,
// by class, intensity or return; pixel-sized or distance-attenuated; points outside the
// cutting volume are not drawn.
#include "include/jet.glsl"
#include "include/viewer_point_style.glsl"
layout(location = 0) in vec3 a_position;   // relative to the chunk centre
layout(location = 1) in vec4 a_rgb;        // 0xLLRRGGBB read as BGRA bytes (L = label)
layout(location = 2) in float a_extra;     // height above ground, or the packed attributes (u_attributes)
uniform mat4 u_model_view;                 // computed in double on the CPU
uniform mat4 u_projection;
uniform float u_chunk_z;                   // chunk centre height (local frame)
uniform vec2 u_chunk_grid_m;               // chunk centre from the terrain grid's origin (x, y)
uniform vec3 u_cut_centre;                 // relative to the chunk centre
out vec4 v_colour;
void main() {
    if (outsideCut(a_position, u_cut_centre)) {
        gl_Position = vec4(2.0, 2.0, 2.0, 1.0);   // outside the clip volume: not drawn
        gl_PointSize = 1.0;
        v_colour = vec4(0.0);
        return;
    }
    vec4 p = u_model_view * vec4(a_position, 1.0);
    gl_Position = u_projection * p;
    v_colour = vec4(viewerPointColour(a_rgb, a_position.z + u_chunk_z, a_extra, a_position.xy + u_chunk_grid_m), 1.0);
    gl_PointSize = viewerPointSize(p.z);
}
