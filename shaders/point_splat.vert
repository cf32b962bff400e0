#version 450 core
// Square point splats of a fixed size (render::PointSplatRenderer): white or per-point
// colours, positions relative to their chunk's centre.
layout(location = 0) in vec3 a_position;   // relative to the chunk centre
layout(location = 1) in vec4 a_colour;     // 0x00RRGGBB read as BGRA bytes
uniform mat4 u_mvp;                        // projection * view * translate(chunk centre)
uniform float u_point_size;
uniform vec4 u_colour;
uniform bool u_use_point_colours;
out vec4 v_colour;
void main() {
    gl_Position = u_mvp * vec4(a_position, 1.0);
    gl_PointSize = u_point_size;
    v_colour = u_use_point_colours ? vec4(a_colour.rgb, 1.0) : u_colour;
}
