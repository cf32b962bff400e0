#version 450 core
// The viewer's overlay (viewer::OverlayRenderer): the pointer's ray and dot, the
// designated point and candidate boxes. Positions arrive in eye space, computed in
// double on the CPU (view * world), so they are exact at any distance from the origin.
layout(location = 0) in vec3 a_eye_position;
layout(location = 1) in vec4 a_colour;
uniform mat4 u_projection;
uniform float u_size_px;                    // point size for the dots
out vec4 v_colour;
void main() {
    gl_Position = u_projection * vec4(a_eye_position, 1.0);
    v_colour = a_colour;
    gl_PointSize = u_size_px;
}
