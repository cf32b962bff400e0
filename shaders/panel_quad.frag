#version 450 core
// The ImGui panel's texture on its quad in the headset, with the panel's own alpha (where
// no window is, the quad is clear: the cloud behind it stays as it is).
in vec2 v_uv;
uniform sampler2D u_panel;
layout(location = 0) out vec4 f_colour;
void main() {
    vec4 c = texture(u_panel, v_uv);
    f_colour = c;
}
