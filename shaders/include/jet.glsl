// The jet colour map of the height colouring (paper section III-C), the same table and indexing
// as the generator's files: u_jet holds core::jetTable(m) (texel i = entry i, RGBA8 from
// 0x00RRGGBB), and an entry is chosen as core::jetIndex chooses it: bin
// floor((z - z_min) / (z_max - z_min) * m) clamped to [0, m-1], reversed so the lowest
// bin is red. z_max <= z_min gives the lowest bin's colour. The GPU computes the bin in
// float, so a height within float rounding of a bin edge may take the neighbouring entry.
uniform sampler1D u_jet;

vec3 jetColour(float z, float z_min, float z_max) {
    int m = textureSize(u_jet, 0);
    int bin = 0;
    if (z_max > z_min)
        bin = clamp(int(floor((z - z_min) / (z_max - z_min) * float(m))), 0, m - 1);
    return texelFetch(u_jet, m - 1 - bin, 0).rgb;
}
