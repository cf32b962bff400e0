// How the viewer shows one point, shared by its GL_POINTS vertex stage and its compute
// rasteriser so both give the same colours and sizes. Needs jet.glsl included before.
uniform float u_z_min;
uniform float u_z_max;
uniform int u_colour_mode;                 // 0 file, 1 height jet, 2 white, 3 label, 4 above ground
uniform float u_above_ground_max_m;        // the cloud's highest height above ground
uniform float u_size_px;
uniform int u_attenuate;
uniform float u_cut_radius;                // cutting volume: < 0 off

// rgb_label: the file's colour and label byte as normalised (R, G, B, L); z: the point's
// height in the local frame.
vec3 viewerPointColour(vec4 rgb_label, float z, float above_ground_m) {
    if (u_colour_mode == 0) return rgb_label.rgb;
    // Above ground on a cloud with no height above ground (no terrain fitted) shows the
    // height colours instead (viewer::shownColourMode; the viewer warns once).
    if (u_colour_mode == 1 || (u_colour_mode == 4 && u_above_ground_max_m <= 0.0))
        return jetColour(z, u_z_min, u_z_max);
    if (u_colour_mode == 2) return vec3(1.0);
    if (u_colour_mode == 4) {
        // The file's whitened ground stays white; the rest by height above the terrain, so a
        // target on a hilltop takes the same colour as one in a valley.
        bool white = all(greaterThanEqual(rgb_label.rgb, vec3(1.0)));
        return white ? vec3(1.0) : jetColour(above_ground_m, 0.0, u_above_ground_max_m);
    }
    int label = int(round(rgb_label.a * 255.0));   // 0 ground, 1 environment, 2 target
    return label == 2 ? vec3(1.0, 0.0, 0.0) : label == 1 ? vec3(0.6) : vec3(0.3);
}

// The side of the point's square in pixels; eye_z: its z in eye space (negative ahead).
float viewerPointSize(float eye_z) {
    float size = u_size_px;
    if (u_attenuate != 0) size = u_size_px * 100.0 / max(-eye_z, 1e-3);
    return clamp(size, 1.0, 64.0);
}

// True when the cutting volume is on and the point (relative to its cell's centre, like
// cut_centre) lies outside it.
bool outsideCut(vec3 position, vec3 cut_centre) {
    return u_cut_radius >= 0.0 && distance(position, cut_centre) > u_cut_radius;
}
