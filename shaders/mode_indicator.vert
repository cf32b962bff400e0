#version 450 core
// The mode indicator's plate: a rectangle in NDC from 4 vertices (triangle strip), no
// vertex attributes.
uniform vec4 u_rect_ndc;   // x0, y0, x1, y1
void main() {
    vec2 c = vec2((gl_VertexID & 1) != 0 ? u_rect_ndc.z : u_rect_ndc.x,
                  (gl_VertexID & 2) != 0 ? u_rect_ndc.w : u_rect_ndc.y);
    gl_Position = vec4(c, 0.0, 1.0);
}
