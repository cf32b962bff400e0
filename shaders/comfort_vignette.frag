#version 450 core
// The headset's comfort vignette while moving in free mode (viewer::OverlayRenderer):
// clear inside `u_aperture` (a fraction of the half view), black beyond it after a fade
// `u_feather` wide, scaled by `u_strength` (0..1, eased in and out with the motion).
uniform vec4 u_viewport;    // x, y, w, h in pixels
uniform float u_aperture;
uniform float u_feather;
uniform float u_strength;
layout(location = 0) out vec4 f_colour;
void main() {
    vec2 p = (gl_FragCoord.xy - u_viewport.xy) / u_viewport.zw * 2.0 - 1.0;
    float a = smoothstep(u_aperture, u_aperture + max(u_feather, 1e-4), length(p)) * u_strength;
    f_colour = vec4(0.0, 0.0, 0.0, a);
}
