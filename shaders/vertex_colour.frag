#version 450 core
// Writes the colour the vertex stage chose (point splats of render and of the viewer).
in vec4 v_colour;
layout(location = 0) out vec4 f_colour;
void main() { f_colour = v_colour; }
