// Eye-space distance (metres) of a depth-buffer value d in [0, 1] written with a GL
// perspective projection (clip depth -1..1) with clip planes near_m and far_m.
float linearDepth(float d, float near_m, float far_m) {
    float z = d * 2.0 - 1.0;
    return 2.0 * near_m * far_m / (far_m + near_m - z * (far_m - near_m));
}
