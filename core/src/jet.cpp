// core/src/jet.cpp: MATLAB's jet colour map and the height-to-entry rule (paper §III-C).
#include <core/jet.hpp>

#include <core/point_cloud.hpp>

#include <algorithm>
#include <cassert>
#include <cmath>

namespace core {

std::vector<std::uint32_t> jetTable(int m) {
    assert(m >= 1);
    // MATLAB's jet.m: n = ceil(m/4); u = [(1:n)/n, ones(1,n-1), (n:-1:1)/n];
    // g = ceil(n/2) - (mod(m,4)==1) + (1:numel(u)); r = g + n; b = g - n.
    const int n = (m + 3) / 4;
    std::vector<double> u;
    for (int i = 1; i <= n; ++i) u.push_back(double(i) / n);
    for (int i = 1; i < n; ++i) u.push_back(1.0);
    for (int i = n; i >= 1; --i) u.push_back(double(i) / n);
    std::vector<double> r(m, 0.0), g(m, 0.0), b(m, 0.0);
    const int g0 = (n + 1) / 2 - (m % 4 == 1 ? 1 : 0);
    for (int k = 0; k < int(u.size()); ++k) {
        const int gi = g0 + k + 1;  // 1-based as in MATLAB
        const int ri = gi + n, bi = gi - n;
        if (gi >= 1 && gi <= m) g[gi - 1] = u[k];
        if (ri >= 1 && ri <= m) r[ri - 1] = u[k];
        if (bi >= 1 && bi <= m) b[bi - 1] = u[k];
    }
    auto to8 = [](double c) { return std::uint8_t(std::lround(std::clamp(c, 0.0, 1.0) * 255.0)); };
    std::vector<std::uint32_t> table(m);
    for (int i = 0; i < m; ++i) table[i] = packRgb(to8(r[i]), to8(g[i]), to8(b[i]));
    return table;
}

int jetIndex(double z, double z_min, double z_max, int m) {
    assert(m >= 1);
    int bin = 0;
    if (z_max > z_min) {
        const double f = (z - z_min) / (z_max - z_min);
        bin = std::clamp(int(std::floor(f * m)), 0, m - 1);  // NaN f cannot occur: z_max > z_min
    }
    return m - 1 - bin;
}

}  // namespace core
