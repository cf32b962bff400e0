// How the viewer shows one point, shared by its GL_POINTS vertex stage and its compute
// rasteriser so both give the same colours and sizes. Needs jet.glsl included before.
uniform float u_z_min;
uniform float u_z_max;
// 0 file, 1 height jet, 2 white, 3 label, 4 above ground, 5 class, 6 intensity, 7 return
uniform int u_colour_mode;
uniform float u_above_ground_max_m;        // the cloud's highest height above ground
uniform float u_size_px;
uniform int u_attenuate;
uniform float u_cut_radius;                // cutting volume: < 0 off
// A terrain under the cloud (viewer::ViewTerrain), when one is bound: ground heights in the
// local frame on a grid of u_terrain_cell, texel (i, j) the height at the grid's origin
// plus (i, j) cells. Points below u_ground_threshold_m above it are ground (white).
uniform int u_terrain_on;
uniform sampler2D u_terrain;
uniform float u_terrain_cell;
uniform float u_ground_threshold_m;
// 1: the per-point float holds the point's attributes (the cloud has no heights above
// ground), an integer: bits 0-7 its ASPRS class, 8-15 its intensity stretched to 0..255,
// 16-18 its return number, 19-21 its pulse's number of returns
// (viewer/src/points/point_attributes.hpp). 0: it holds the height above ground.
uniform int u_attributes;
// 1 (with u_attributes 0): the heights above ground are another producer's file's (`ladarvr
// ground` writes them beside its class 2): its ground is the points labelled ground (class 2),
// since its colours are its own. 0: the generator's cloud, whose colours whiten its ground.
uniform int u_ground_by_label;

// The terrain's height at `grid_m` (metres from the grid's origin along x and y), bilinear
// between the four nearest cells' centres, the edge cells' heights beyond the grid; the
// same sums as viewer::PointRenderer's CPU copy.
float terrainHeight(vec2 grid_m) {
    ivec2 n = textureSize(u_terrain, 0);
    vec2 g = clamp(grid_m / u_terrain_cell, vec2(0.0), vec2(n - 1));
    ivec2 i0 = ivec2(floor(g));
    ivec2 i1 = min(i0 + 1, n - 1);
    vec2 f = g - vec2(i0);
    float z00 = texelFetch(u_terrain, i0, 0).r, z10 = texelFetch(u_terrain, ivec2(i1.x, i0.y), 0).r;
    float z01 = texelFetch(u_terrain, ivec2(i0.x, i1.y), 0).r, z11 = texelFetch(u_terrain, i1, 0).r;
    return mix(mix(z00, z10, f.x), mix(z01, z11, f.x), f.y);
}

// The ASPRS standard classes' colours (docs/viewer.md's table), as bytes so that they reach
// the screen exactly.
vec3 classColour(uint c) {
    if (c == 2u) return vec3(153.0, 102.0, 51.0) / 255.0;      // ground: brown
    if (c == 3u) return vec3(150.0, 220.0, 110.0) / 255.0;     // low vegetation: light green
    if (c == 4u) return vec3(60.0, 180.0, 60.0) / 255.0;       // medium vegetation: green
    if (c == 5u) return vec3(0.0, 115.0, 0.0) / 255.0;         // high vegetation: dark green
    if (c == 6u) return vec3(230.0, 100.0, 40.0) / 255.0;      // building: orange red
    if (c == 9u) return vec3(40.0, 100.0, 230.0) / 255.0;      // water: blue
    if (c == 7u || c == 18u) return vec3(255.0, 0.0, 255.0) / 255.0;   // low / high noise: magenta
    return vec3(153.0) / 255.0;                                // any other: grey
}

// Single returns yellow, the first of several green, intermediate ones blue, the last red.
vec3 returnColour(uint number, uint returns) {
    if (number == 0u || returns == 0u) return vec3(153.0) / 255.0;   // not recorded: grey
    if (returns == 1u) return vec3(255.0, 215.0, 0.0) / 255.0;
    if (number == 1u) return vec3(0.0, 205.0, 75.0) / 255.0;
    if (number >= returns) return vec3(230.0, 40.0, 40.0) / 255.0;
    return vec3(65.0, 115.0, 255.0) / 255.0;
}

// rgb_label: the file's colour and label byte as normalised (R, G, B, L); z: the point's
// height in the local frame; extra: the per-point float (u_attributes); grid_m: the
// point's horizontal position from the terrain grid's origin (used when one is bound).
vec3 viewerPointColour(vec4 rgb_label, float z, float extra, vec2 grid_m) {
    if (u_colour_mode == 0) return rgb_label.rgb;
    int label = int(round(rgb_label.a * 255.0));   // 0 ground, 1 environment, 2 target
    uint word = u_attributes != 0 ? uint(extra) : 0u;
    if (u_colour_mode == 5)   // a cloud without attributes: the class our LAS writer gives its label
        return classColour(u_attributes != 0 ? (word & 0xFFu) : label == 0 ? 2u : label == 1 ? 1u : 64u);
    if (u_colour_mode == 6 && u_attributes != 0) return vec3(float((word >> 8) & 0xFFu) / 255.0);
    if (u_colour_mode == 7 && u_attributes != 0) return returnColour((word >> 16) & 7u, (word >> 19) & 7u);
    if (u_colour_mode == 4 && u_terrain_on != 0) {
        // Height above the bound terrain: ground white, the rest the jet over [0, the highest].
        float h = z - terrainHeight(grid_m);
        return h < u_ground_threshold_m ? vec3(1.0) : jetColour(h, 0.0, u_above_ground_max_m);
    }
    // Above ground on a cloud with no height above ground (no terrain fitted, none bound)
    // shows the height colours instead (viewer::shownColourMode; the viewer warns once), as
    // intensity and return do on a cloud that does not carry them.
    if (u_colour_mode == 1 || (u_colour_mode == 4 && (u_attributes != 0 || u_above_ground_max_m <= 0.0)) ||
        u_colour_mode >= 6)
        return jetColour(z, u_z_min, u_z_max);
    if (u_colour_mode == 2) return vec3(1.0);
    if (u_colour_mode == 4) {
        // The ground white (the generator's whitened points, or another producer's class 2);
        // the rest by height above the terrain, so a target on a hilltop takes the same
        // colour as one in a valley.
        bool white = u_ground_by_label != 0 ? label == 0 : all(greaterThanEqual(rgb_label.rgb, vec3(1.0)));
        return white ? vec3(1.0) : jetColour(extra, 0.0, u_above_ground_max_m);
    }
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
