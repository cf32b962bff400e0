// shaders/include/viewer_points_splat.glsl: the viewer's points rasterised in compute
// (viewer::Rasterizer::Compute), one invocation per point (grid-stride) over one chunk's
// drawn cells; the body of viewer_points_splat.comp and, with LADARVR_SUBGROUP defined,
// of viewer_points_splat_subgroup.comp. Pass 0 keeps each pixel's nearest depth (atomic
// minimum of the window depth's bits: non-negative floats order as their bits do); pass 1
// gives the pixel the colour of a point at that depth (atomic minimum of the packed
// colour, so a tie between points at the same depth resolves the same way in any order).
// Squares as GL rasterises points: the pixels whose centres fall in [win - s/2, win + s/2),
// for points whose centre lies in the view volume.
//
// Early depth test: pass 0 reads the pixel first and issues the atomic only when the point
// is nearer (Schuetz, Kerbl and Wimmer, EGSR 2021). With LADARVR_SUBGROUP, when every
// active invocation of a subgroup covers the same pixels (distant points of a node, which
// the LOD order keeps together), the subgroup first reduces them (the least depth in pass
// 0; in pass 1, per pixel, the least colour among the points at the pixel's depth) and one
// invocation issues the atomics. A minimum of minima is the same minimum, so the images
// are the same bits as without it.
#include "jet.glsl"
#include "viewer_point_style.glsl"
layout(local_size_x = 128) in;
struct Cell {
    mat4 model_view;   // view * translate(cell centre), folded in double on the CPU
    vec4 cut_centre;   // xyz: the cutting volume's centre relative to the cell's centre; w: the centre's height
    uvec4 range;       // x: first point in the chunk, y: points drawn, z: first invocation index
    vec4 grid;         // xy: the cell's centre from the terrain grid's origin (viewer_point_style.glsl)
};
layout(std430, binding = 1) readonly buffer Points { uint words[]; };   // render::GpuPoint, 5 words each
layout(std430, binding = 2) readonly buffer Cells { Cell cells[]; };
layout(binding = 0, r32ui) uniform coherent uimage2D u_depth_bits;
layout(binding = 1, r32ui) uniform coherent uimage2D u_colour_bits;
uniform mat4 u_projection;
uniform uint u_cell_first;     // this chunk's cells in `cells`
uniform uint u_cell_count;
uniform uint u_total;          // points drawn from them
uniform vec2 u_image_size;     // the eye target, pixels
uniform int u_pass;

/// The point's packed colour (rgba8 as the resolve reads it).
uint pointColour(uint i, vec3 position, uint cell) {
    uint w = words[i + 3u];   // 0xLLRRGGBB
    vec4 rgb_label = unpackUnorm4x8(w).zyxw;
    float z = position.z + cells[cell].cut_centre.w;
    vec2 grid_m = position.xy + cells[cell].grid.xy;
    return packUnorm4x8(vec4(viewerPointColour(rgb_label, z, uintBitsToFloat(words[i + 4u]), grid_m), 1.0));
}

void main() {
    uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
    for (uint v = gl_GlobalInvocationID.x; v < u_total; v += stride) {
        uint lo = u_cell_first, hi = u_cell_first + u_cell_count - 1u;
        while (lo < hi) {
            uint mid = (lo + hi + 1u) / 2u;
            if (cells[mid].range.z <= v) lo = mid; else hi = mid - 1u;
        }
        uint i = 5u * (cells[lo].range.x + (v - cells[lo].range.z));
        vec3 position = vec3(uintBitsToFloat(words[i]), uintBitsToFloat(words[i + 1u]), uintBitsToFloat(words[i + 2u]));
        if (outsideCut(position, cells[lo].cut_centre.xyz)) continue;
        vec4 p = cells[lo].model_view * vec4(position, 1.0);
        vec4 c = u_projection * p;
        if (c.w <= 0.0 || abs(c.x) > c.w || abs(c.y) > c.w || abs(c.z) > c.w) continue;
        vec3 ndc = c.xyz / c.w;
        uint depth_bits = floatBitsToUint(max(ndc.z * 0.5 + 0.5, 0.0));
        vec2 win = (ndc.xy * 0.5 + 0.5) * u_image_size;
        float s = viewerPointSize(p.z);
        ivec2 first = max(ivec2(ceil(win - 0.5 * s - 0.5)), ivec2(0));
        ivec2 last = min(ivec2(ceil(win + 0.5 * s - 0.5)), ivec2(u_image_size));
#ifdef LADARVR_SUBGROUP
        if (subgroupAllEqual(first) && subgroupAllEqual(last)) {
            // The same pixels for every active invocation: reduce, then one atomic a pixel.
            if (u_pass == 0) {
                uint nearest = subgroupMin(depth_bits);
                if (subgroupElect())
                    for (int y = first.y; y < last.y; ++y)
                        for (int x = first.x; x < last.x; ++x) {
                            ivec2 q = ivec2(x, y);
                            if (nearest < imageLoad(u_depth_bits, q).r) imageAtomicMin(u_depth_bits, q, nearest);
                        }
                continue;
            }
            uint colour_bits = pointColour(i, position, lo);
            for (int y = first.y; y < last.y; ++y)
                for (int x = first.x; x < last.x; ++x) {
                    ivec2 q = ivec2(x, y);
                    uint mine = imageLoad(u_depth_bits, q).r == depth_bits ? colour_bits : 0xFFFFFFFFu;
                    uint least = subgroupMin(mine);
                    if (least != 0xFFFFFFFFu && subgroupElect()) imageAtomicMin(u_colour_bits, q, least);
                }
            continue;
        }
#endif
        if (u_pass == 0) {
            for (int y = first.y; y < last.y; ++y)
                for (int x = first.x; x < last.x; ++x) {
                    ivec2 q = ivec2(x, y);
                    if (depth_bits < imageLoad(u_depth_bits, q).r) imageAtomicMin(u_depth_bits, q, depth_bits);
                }
            continue;
        }
        uint colour_bits = 0u;
        bool coloured = false;
        for (int y = first.y; y < last.y; ++y)
            for (int x = first.x; x < last.x; ++x) {
                ivec2 q = ivec2(x, y);
                if (imageLoad(u_depth_bits, q).r != depth_bits) continue;
                if (!coloured) {
                    colour_bits = pointColour(i, position, lo);
                    coloured = true;
                }
                imageAtomicMin(u_colour_bits, q, colour_bits);
            }
    }
}
