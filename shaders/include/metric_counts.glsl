// The metric's pixel counts (paper section IV-B): i1, i2, i3, i2 xor i3 (I4), i3 and not i2
// (visible target), depth-visible and i1. Shared-memory partial sums, one global atomic
// per workgroup and counter. The including stage defines `uint bitsAt(ivec2 p)`: bit 0
// I1, bit 1 I2, bit 2 I3, bit 3 nearer than P2 by the depth margin.
layout(local_size_x = 16, local_size_y = 16) in;
layout(std430, binding = 0) buffer Counts { uint counts[8]; };
uniform ivec2 u_offset;   // first counted pixel
uniform ivec2 u_size;     // counted pixels
shared uint s_counts[6];
void main() {
    uint i = gl_LocalInvocationIndex;
    if (i < 6u) s_counts[i] = 0u;
    barrier();
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (p.x < u_size.x && p.y < u_size.y) {
        uint b = bitsAt(u_offset + p);
        bool i1 = (b & 1u) != 0u, i2 = (b & 2u) != 0u, i3 = (b & 4u) != 0u, near = (b & 8u) != 0u;
        if (i1) atomicAdd(s_counts[0], 1u);
        if (i2) atomicAdd(s_counts[1], 1u);
        if (i3) atomicAdd(s_counts[2], 1u);
        if (i2 != i3) atomicAdd(s_counts[3], 1u);     // I4 = I2 xor I3
        if (i3 && !i2) atomicAdd(s_counts[4], 1u);    // visible target
        if (near && i1) atomicAdd(s_counts[5], 1u);   // depth-aware visible target
    }
    barrier();
    if (i < 6u && s_counts[i] != 0u) atomicAdd(counts[i], s_counts[i]);
}
