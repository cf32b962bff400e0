#version 450 core
// The ImGui panel shown in the headset (viewer::OverlayRenderer::drawPanelQuad): a quad in
// the tracking frame, its corners given in eye space (computed in double on the CPU).
layout(location = 0) in vec3 a_eye_position;
layout(location = 1) in vec2 a_uv;
uniform mat4 u_projection;
out vec2 v_uv;
void main() {
    gl_Position = u_projection * vec4(a_eye_position, 1.0);
    v_uv = a_uv;
}
