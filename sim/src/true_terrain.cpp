// sim/src/true_terrain.cpp: see true_terrain.hpp.
#include "true_terrain.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace sim {

TrueTerrain::TrueTerrain(const core::Scene& scene, double cx, double cy, double half_m, double min_cell_m,
                         std::size_t max_cells) {
    bool any = false;
    for (const core::Mesh& m : scene.meshes) any |= m.role == core::Role::Ground && !m.triangles.empty();
    if (!any || !(half_m > 0)) return;
    const double side_cells = std::sqrt(double(max_cells));
    cell_m_ = std::max(min_cell_m, 2.0 * half_m / std::max(1.0, side_cells - 1.0));
    nx_ = ny_ = int(std::ceil(2.0 * half_m / cell_m_)) + 1;
    x0_m_ = cx - half_m;
    y0_m_ = cy - half_m;
    z_m_.assign(std::size_t(nx_) * std::size_t(ny_), std::numeric_limits<float>::quiet_NaN());
    for (const core::Mesh& m : scene.meshes) {
        if (m.role != core::Role::Ground) continue;
        for (const glm::uvec3& t : m.triangles) {
            const glm::dvec3 a(m.vertices[t[0]]), b(m.vertices[t[1]]), c(m.vertices[t[2]]);
            const double det = (b.y - c.y) * (a.x - c.x) + (c.x - b.x) * (a.y - c.y);
            if (std::abs(det) < 1e-12) continue;  // vertical or degenerate: no height of its own
            const auto cellRange = [&](double lo, double hi, double origin, int n, int& i0, int& i1) {
                i0 = std::max(0, int(std::ceil((lo - origin) / cell_m_)));
                i1 = std::min(n - 1, int(std::floor((hi - origin) / cell_m_)));
            };
            int i0, i1, j0, j1;
            cellRange(std::min({a.x, b.x, c.x}), std::max({a.x, b.x, c.x}), x0_m_, nx_, i0, i1);
            cellRange(std::min({a.y, b.y, c.y}), std::max({a.y, b.y, c.y}), y0_m_, ny_, j0, j1);
            for (int j = j0; j <= j1; ++j)
                for (int i = i0; i <= i1; ++i) {
                    const double x = x0_m_ + i * cell_m_, y = y0_m_ + j * cell_m_;
                    const double wa = ((b.y - c.y) * (x - c.x) + (c.x - b.x) * (y - c.y)) / det;
                    const double wb = ((c.y - a.y) * (x - c.x) + (a.x - c.x) * (y - c.y)) / det;
                    const double wc = 1.0 - wa - wb;
                    constexpr double kEdge = -1e-9;
                    if (wa < kEdge || wb < kEdge || wc < kEdge) continue;
                    const float z = float(wa * a.z + wb * b.z + wc * c.z);
                    float& cell = z_m_[std::size_t(j) * std::size_t(nx_) + std::size_t(i)];
                    if (std::isnan(cell) || z > cell) cell = z;
                }
        }
    }
}

bool TrueTerrain::heightAt(double x, double y, double& z_m) const {
    if (empty()) return false;
    const double fx = (x - x0_m_) / cell_m_, fy = (y - y0_m_) / cell_m_;
    if (!(fx >= 0 && fy >= 0 && fx <= nx_ - 1 && fy <= ny_ - 1)) return false;
    const int i0 = std::min(int(fx), nx_ - 2 < 0 ? 0 : nx_ - 2), j0 = std::min(int(fy), ny_ - 2 < 0 ? 0 : ny_ - 2);
    const int i1 = std::min(i0 + 1, nx_ - 1), j1 = std::min(j0 + 1, ny_ - 1);
    const double tx = fx - i0, ty = fy - j0;
    const auto at = [&](int i, int j) { return double(z_m_[std::size_t(j) * std::size_t(nx_) + std::size_t(i)]); };
    const double z00 = at(i0, j0), z10 = at(i1, j0), z01 = at(i0, j1), z11 = at(i1, j1);
    if (std::isnan(z00) || std::isnan(z10) || std::isnan(z01) || std::isnan(z11)) {
        const double nearest = at(tx < 0.5 ? i0 : i1, ty < 0.5 ? j0 : j1);  // at a ground mesh's edge
        if (std::isnan(nearest)) return false;
        z_m = nearest;
        return true;
    }
    z_m = (1 - ty) * ((1 - tx) * z00 + tx * z10) + ty * ((1 - tx) * z01 + tx * z11);
    return true;
}

}  // namespace sim
