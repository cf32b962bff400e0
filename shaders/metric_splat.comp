#version 450 core
// The metric's images I1, I2, I3 as bits of one r32ui mask (paper section IV-B steps 1-3), one
// invocation per point (grid-stride), square splats as GL rasterises points. `ranges`
// lists the cells kept by culling as (first point, first virtual index) pairs; a binary
// search maps a virtual index to a point.
layout(local_size_x = 128) in;
layout(std430, binding = 1) readonly buffer Points { vec4 points[]; };
layout(std430, binding = 2) readonly buffer Ranges { uvec2 ranges[]; };
layout(binding = 0, r32ui) uniform coherent uimage2D u_mask;
layout(binding = 1, r32ui) uniform coherent uimage2D u_depth;
uniform mat4 u_mvp;            // projection * view * translate(cloud centre), folded in double
uniform mat4 u_mv;             // view * translate(cloud centre)
uniform uint u_range_count;
uniform uint u_total;          // points in the kept cells
uniform vec2 u_image_size;     // the whole image, pixels
uniform ivec2 u_region_origin; // drawn region, image pixels; mask pixel = image pixel - origin
uniform ivec2 u_region_size;
uniform float u_splat;         // square side, pixels
uniform uint u_bit;
uniform int u_mode;            // 0 set bit; 1 also keep nearest distance; 2 also bit 8 if nearer
uniform float u_margin_m;
void main() {
    uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
    for (uint v = gl_GlobalInvocationID.x; v < u_total; v += stride) {
        uint lo = 0u, hi = u_range_count - 1u;
        while (lo < hi) {
            uint mid = (lo + hi + 1u) / 2u;
            if (ranges[mid].y <= v) lo = mid; else hi = mid - 1u;
        }
        vec4 p = vec4(points[ranges[lo].x + (v - ranges[lo].y)].xyz, 1.0);
        vec4 c = u_mvp * p;
        // As GL clips points: the centre must lie in the view volume.
        if (c.w <= 0.0 || abs(c.x) > c.w || abs(c.y) > c.w || abs(c.z) > c.w) continue;
        vec2 win = (c.xy / c.w * 0.5 + 0.5) * u_image_size;
        // Pixels whose centres fall in [win - s/2, win + s/2), as GL rasterises a point.
        ivec2 first = ivec2(ceil(win - 0.5 * u_splat - 0.5)) - u_region_origin;
        ivec2 last = ivec2(ceil(win + 0.5 * u_splat - 0.5)) - u_region_origin;
        first = max(first, ivec2(0));
        last = min(last, u_region_size);
        if (first.x >= last.x || first.y >= last.y) continue;
        float dist = (u_mode != 0) ? length((u_mv * p).xyz) : 0.0;
        uint dist_bits = floatBitsToUint(dist);
        uint near_bits = floatBitsToUint(dist + u_margin_m);
        for (int y = first.y; y < last.y; ++y)
            for (int x = first.x; x < last.x; ++x) {
                ivec2 q = ivec2(x, y);
                uint bits = u_bit;
                if (u_mode == 1) imageAtomicMin(u_depth, q, dist_bits);
                if (u_mode == 2 && near_bits < imageLoad(u_depth, q).r) bits |= 8u;
                if ((imageLoad(u_mask, q).r & bits) != bits) imageAtomicOr(u_mask, q, bits);
            }
    }
}
