// bench/src/ground_isprs_mcc.cpp: see ground_isprs_mcc.hpp. Everything runs on rasters built
// here from the points in memory (one sample at a time, a few rasters of at most 2^24 cells
// each), serially, so two runs print the same figures.
#include "ground_isprs_mcc.hpp"

#include "common.hpp"
#include "ground_isprs_selector_fits.hpp"

#include <core/error.hpp>
#include <core/point_cloud.hpp>
#include <sim/ground_file.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <string>

namespace bench {
namespace {

/// A raster may hold at most this many cells (the samples need a few hundred thousand).
constexpr std::size_t kMaxCells = std::size_t(1) << 24;
/// Relaxation sweeps after the push-pull fill: the pyramid already gives each hole a
/// smooth value, the sweeps take off its blocks' seams.
constexpr int kFillSweeps = 20;
constexpr double kOverRelaxation = 1.5;
/// A plane is fitted to heights only where their positions spread at least this many cells
/// (one standard deviation) across the narrower way; else their mean is taken.
constexpr double kPlaneSpread = 0.15;

/// The least-squares sums of heights over positions, for the plane through them.
struct Moments {
    double n = 0, x = 0, y = 0, z = 0, xx = 0, xy = 0, yy = 0, xz = 0, yz = 0;
    void add(double px, double py, double pz) {
        n += 1, x += px, y += py, z += pz;
        xx += px * px, xy += px * py, yy += py * py, xz += px * pz, yz += py * pz;
    }
    void add(const Moments& o) {
        n += o.n, x += o.x, y += o.y, z += o.z;
        xx += o.xx, xy += o.xy, yy += o.yy, xz += o.xz, yz += o.yz;
    }
    /// Whether the positions spread at least `min_spread` across the narrower way (not
    /// too few, not along a line), so that a plane through them is defined.
    bool planar(double min_spread) const {
        if (n < 3) return false;
        const double mx = x / n, my = y / n;
        const double sxx = xx / n - mx * mx, sxy = xy / n - mx * my, syy = yy / n - my * my;
        const double det = sxx * syy - sxy * sxy, half = (sxx + syy) / 2;
        return det > 0 && half - std::sqrt(std::max(0.0, half * half - det)) >= min_spread * min_spread;
    }
    /// The plane's height at (cx, cy); the mean height where !planar(min_spread). Needs n > 0.
    double at(double cx, double cy, double min_spread) const {
        const double mx = x / n, my = y / n, mz = z / n;
        if (!planar(min_spread)) return mz;
        const double sxx = xx / n - mx * mx, sxy = xy / n - mx * my, syy = yy / n - my * my;
        const double sxz = xz / n - mx * mz, syz = yz / n - my * mz;
        const double det = sxx * syy - sxy * sxy;
        const double a = (sxz * syy - syz * sxy) / det, b = (syz * sxx - sxz * sxy) / det;
        return mz + a * (cx - mx) + b * (cy - my);
    }
};

// Bilinear between the values at cell centres (u, v in cells from the first centre);
// beyond the outer centres the last two carry on linearly (a slope stays a slope to the
// raster's edge).
float bilinear(const std::vector<float>& z, int nx, int ny, double u, double v) {
    const int i0 = nx > 1 ? std::clamp(int(std::floor(u)), 0, nx - 2) : 0;
    const int j0 = ny > 1 ? std::clamp(int(std::floor(v)), 0, ny - 2) : 0;
    const int i1 = std::min(i0 + 1, nx - 1), j1 = std::min(j0 + 1, ny - 1);
    const double fu = nx > 1 ? u - i0 : 0.0, fv = ny > 1 ? v - j0 : 0.0;
    const auto at = [&](int i, int j) { return double(z[std::size_t(j) * std::size_t(nx) + std::size_t(i)]); };
    return float((1 - fv) * ((1 - fu) * at(i0, j0) + fu * at(i1, j0)) + fv * ((1 - fu) * at(i0, j1) + fu * at(i1, j1)));
}

void smooth3x3(HeightRaster& r) {
    std::vector<float> out(r.z_m.size());
    for (int j = 0; j < r.ny; ++j)
        for (int i = 0; i < r.nx; ++i) {
            double sum = 0;
            int count = 0;
            for (int b = std::max(0, j - 1); b <= std::min(r.ny - 1, j + 1); ++b)
                for (int a = std::max(0, i - 1); a <= std::min(r.nx - 1, i + 1); ++a)
                    sum += r.z_m[r.index(a, b)], ++count;
            out[r.index(i, j)] = float(sum / count);
        }
    r.z_m = std::move(out);
}

double medianOf(std::vector<double> v) {
    if (v.empty()) return 0.0;
    const std::size_t mid = v.size() / 2;
    std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(mid), v.end());
    return v[mid];
}

}  // namespace

HeightRaster HeightRaster::spanning(const std::vector<core::CloudPoint>& points, double cell_m) {
    HeightRaster r;
    r.cell_m = cell_m;
    if (points.empty()) return r;
    double x1 = -std::numeric_limits<double>::max(), y1 = x1;
    r.x0_m = r.y0_m = std::numeric_limits<double>::max();
    for (const core::CloudPoint& p : points) {
        r.x0_m = std::min(r.x0_m, double(p.position.x)), r.y0_m = std::min(r.y0_m, double(p.position.y));
        x1 = std::max(x1, double(p.position.x)), y1 = std::max(y1, double(p.position.y));
    }
    const double nx = std::floor((x1 - r.x0_m) / cell_m) + 1, ny = std::floor((y1 - r.y0_m) / cell_m) + 1;
    if (nx * ny > double(kMaxCells))
        throw core::Error("bench ground-isprs --multiscale: the sample spans " + fmt("%.0f", nx * ny) + " cells of " +
                          fmt("%g", cell_m) + " m; allowed at most 16,777,216");
    r.nx = int(nx), r.ny = int(ny);
    r.z_m.assign(std::size_t(r.nx) * std::size_t(r.ny), 0.0f);
    return r;
}

int HeightRaster::column(double x) const { return std::clamp(int(std::floor((x - x0_m) / cell_m)), 0, nx - 1); }
int HeightRaster::row(double y) const { return std::clamp(int(std::floor((y - y0_m) / cell_m)), 0, ny - 1); }

double HeightRaster::heightAt(double x, double y) const {
    return bilinear(z_m, nx, ny, (x - x0_m) / cell_m - 0.5, (y - y0_m) / cell_m - 0.5);
}

double HeightRaster::slopeAt(double x, double y) const {
    const int i = column(x), j = row(y);
    const int i0 = std::max(i - 1, 0), i1 = std::min(i + 1, nx - 1), j0 = std::max(j - 1, 0),
              j1 = std::min(j + 1, ny - 1);
    const double dx = i1 > i0 ? (z_m[index(i1, j)] - z_m[index(i0, j)]) / ((i1 - i0) * cell_m) : 0.0;
    const double dy = j1 > j0 ? (z_m[index(i, j1)] - z_m[index(i, j0)]) / ((j1 - j0) * cell_m) : 0.0;
    return std::sqrt(dx * dx + dy * dy);
}

void fillHoles(std::vector<float>& z, const std::vector<std::uint8_t>& known, int nx, int ny, int sweeps) {
    const bool any = std::find(known.begin(), known.end(), std::uint8_t(1)) != known.end();
    const bool all = std::find(known.begin(), known.end(), std::uint8_t(0)) == known.end();
    if (!any || all) return;
    // Each level's cells hold the moments of the known cells beneath them (positions in
    // cells of the first level), so a cell's value is the plane through them at its centre.
    struct Level {
        int nx, ny;
        std::vector<float> z;
        std::vector<std::uint8_t> known;
        std::vector<Moments> m;
    };
    std::vector<Level> levels;
    levels.push_back({nx, ny, z, known, std::vector<Moments>(z.size())});
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
            const std::size_t k = std::size_t(j) * std::size_t(nx) + std::size_t(i);
            if (known[k]) levels[0].m[k].add(i + 0.5, j + 0.5, z[k]);
        }
    // Up, until a level is whole.
    for (double size = 2; std::find(levels.back().known.begin(), levels.back().known.end(), std::uint8_t(0)) !=
                          levels.back().known.end();
         size *= 2) {
        const Level& f = levels.back();
        Level c{(f.nx + 1) / 2, (f.ny + 1) / 2, {}, {}, {}};
        c.z.assign(std::size_t(c.nx) * std::size_t(c.ny), 0.0f);
        c.known.assign(c.z.size(), 0);
        c.m.resize(c.z.size());
        for (int j = 0; j < f.ny; ++j)
            for (int i = 0; i < f.nx; ++i) {
                const std::size_t k = std::size_t(j) * std::size_t(f.nx) + std::size_t(i);
                c.m[std::size_t(j / 2) * std::size_t(c.nx) + std::size_t(i / 2)].add(f.m[k]);
            }
        for (int j = 0; j < c.ny; ++j)
            for (int i = 0; i < c.nx; ++i) {
                const std::size_t p = std::size_t(j) * std::size_t(c.nx) + std::size_t(i);
                // A cell whose known cells do not span a plane takes the value of the
                // level above instead (their mean stands off its centre), unless it is the
                // last level.
                // The spread asked for is a share of the part of the cell inside the raster.
                const bool last = c.nx == 1 && c.ny == 1;
                const double inside = std::min(std::min((i + 1) * size, double(nx)) - i * size,
                                               std::min((j + 1) * size, double(ny)) - j * size);
                const double min_spread = kPlaneSpread * inside;
                if (c.m[p].n == 0 || (!last && !c.m[p].planar(min_spread))) continue;
                c.z[p] = float(c.m[p].at((i + 0.5) * size, (j + 0.5) * size, min_spread));
                c.known[p] = 1;
            }
        levels.push_back(std::move(c));
    }
    // Down: an unknown cell takes the level above's bilinear value at its centre.
    for (std::size_t l = levels.size() - 1; l-- > 0;) {
        Level& f = levels[l];
        const Level& c = levels[l + 1];
        for (int j = 0; j < f.ny; ++j)
            for (int i = 0; i < f.nx; ++i) {
                const std::size_t k = std::size_t(j) * std::size_t(f.nx) + std::size_t(i);
                if (!f.known[k]) f.z[k] = bilinear(c.z, c.nx, c.ny, (i + 0.5) / 2.0 - 0.5, (j + 0.5) / 2.0 - 0.5);
            }
    }
    z = std::move(levels[0].z);
    for (int s = 0; s < sweeps; ++s)
        for (int j = 0; j < ny; ++j)
            for (int i = 0; i < nx; ++i) {
                const std::size_t k = std::size_t(j) * std::size_t(nx) + std::size_t(i);
                if (known[k]) continue;
                // At the raster's edge the missing neighbour is the one inside mirrored
                // through the cell (no bend across the edge), so a plane stays a plane.
                double sum = 0;
                int count = 0;
                if (nx > 1) {
                    sum += i > 0 && i + 1 < nx ? double(z[k - 1]) + z[k + 1] : 2.0 * z[k];
                    count += 2;
                }
                if (ny > 1) {
                    sum += j > 0 && j + 1 < ny ? double(z[k - std::size_t(nx)]) + z[k + std::size_t(nx)] : 2.0 * z[k];
                    count += 2;
                }
                if (count > 0) z[k] += float(kOverRelaxation * (sum / count - z[k]));
            }
}

HeightRaster surfaceThrough(const std::vector<core::CloudPoint>& points, const std::vector<std::uint8_t>& use,
                            double cell_m, bool smooth) {
    HeightRaster r = HeightRaster::spanning(points, cell_m);
    std::vector<Moments> m(r.z_m.size());
    for (std::size_t i = 0; i < points.size(); ++i) {
        if (!use[i]) continue;
        const glm::vec3& p = points[i].position;
        m[r.index(r.column(p.x), r.row(p.y))].add(p.x - r.x0_m, p.y - r.y0_m, p.z);
    }
    // A cell's value is its points' mean height moved to its centre along the plane through
    // the points of its 3 x 3 cells (a point lies up to half a cell from the centre, which
    // on a slope of 0.5 is 0.35 m at 1 m cells).
    std::vector<std::uint8_t> known(r.z_m.size(), 0);
    for (int j = 0; j < r.ny; ++j)
        for (int i = 0; i < r.nx; ++i) {
            const Moments& own = m[r.index(i, j)];
            if (own.n == 0) continue;
            // The nearest 3 x 3, 5 x 5 ... up to 9 x 9 cells whose points span a plane.
            const double spread = kPlaneSpread * cell_m;
            Moments around;
            for (int reach = 1; reach <= 4; ++reach) {
                around = Moments{};
                for (int b = std::max(0, j - reach); b <= std::min(r.ny - 1, j + reach); ++b)
                    for (int a = std::max(0, i - reach); a <= std::min(r.nx - 1, i + reach); ++a)
                        around.add(m[r.index(a, b)]);
                if (around.planar(spread)) break;
            }
            const double cx = (i + 0.5) * cell_m, cy = (j + 0.5) * cell_m;
            const double mx = own.x / own.n, my = own.y / own.n;
            r.z_m[r.index(i, j)] = float(own.z / own.n + around.at(cx, cy, spread) - around.at(mx, my, spread));
            known[r.index(i, j)] = 1;
        }
    fillHoles(r.z_m, known, r.nx, r.ny, kFillSweeps);
    if (smooth) smooth3x3(r);
    return r;
}

std::vector<std::uint8_t> lowOutliers(const std::vector<core::CloudPoint>& points, double drop_m) {
    std::vector<std::uint8_t> low(points.size(), 0);
    if (points.empty() || drop_m <= 0) return low;
    // Each 1 m cell's two lowest heights.
    const HeightRaster r = HeightRaster::spanning(points, 1.0);
    constexpr float kNone = std::numeric_limits<float>::infinity();
    std::vector<float> lowest(r.z_m.size(), kNone), next(r.z_m.size(), kNone);
    for (const core::CloudPoint& p : points) {
        const std::size_t k = r.index(r.column(p.position.x), r.row(p.position.y));
        if (p.position.z < lowest[k])
            next[k] = lowest[k], lowest[k] = p.position.z;
        else
            next[k] = std::min(next[k], p.position.z);
    }
    // As `ladarvr ground` does: a point is a low outlier when it lies that far below every
    // other height around it (the lowest of the other cells within 2 cells, the next one
    // of its own).
    for (std::size_t i = 0; i < points.size(); ++i) {
        const glm::vec3& p = points[i].position;
        const int ci = r.column(p.x), cj = r.row(p.y);
        const std::size_t own = r.index(ci, cj);
        double around = p.z > lowest[own] ? lowest[own] : next[own];
        for (int j = std::max(0, cj - 2); j <= std::min(r.ny - 1, cj + 2); ++j)
            for (int c = std::max(0, ci - 2); c <= std::min(r.nx - 1, ci + 2); ++c)
                if (c != ci || j != cj) around = std::min(around, double(lowest[r.index(c, j)]));
        low[i] = std::isfinite(around) && p.z < around - drop_m;
    }
    return low;
}

std::vector<std::uint8_t> mccGround(const std::vector<core::CloudPoint>& points, const MccOptions& o,
                                    const std::vector<std::uint8_t>* start) {
    std::vector<std::uint8_t> ground = start ? *start : std::vector<std::uint8_t>(points.size(), 1);
    const std::vector<std::uint8_t> low = lowOutliers(points, o.low_outlier_m);
    for (std::size_t i = 0; i < points.size(); ++i)
        if (low[i]) ground[i] = 0;
    // The paper's three scale domains: cells of 0.5, 1 and 1.5 lambda, the tolerance one
    // step wider each, iterated until under 1 %, 0.1 % and 0.01 % of the ground go.
    const double kScale[] = {0.5, 1.0, 1.5}, kConverged[] = {0.01, 0.001, 0.0001};
    for (int s = 0; s < 3; ++s) {
        const double cell_m = o.scale_m * kScale[s], tolerance_m = o.tolerance_m + s * o.tolerance_step_m;
        for (int iteration = 0; iteration < o.max_iterations; ++iteration) {
            const auto count = std::size_t(std::count(ground.begin(), ground.end(), std::uint8_t(1)));
            if (count == 0) break;
            const HeightRaster surface = surfaceThrough(points, ground, cell_m, true);
            std::size_t dropped = 0;
            for (std::size_t i = 0; i < points.size(); ++i) {
                if (!ground[i]) continue;
                const glm::vec3& p = points[i].position;
                if (p.z - surface.heightAt(p.x, p.y) <= tolerance_m) continue;
                if (o.min_slope > 0 || o.max_slope > 0) {
                    const double slope = surface.slopeAt(p.x, p.y);
                    if ((o.min_slope > 0 && slope <= o.min_slope) || (o.max_slope > 0 && slope >= o.max_slope))
                        continue;
                }
                ground[i] = 0;
                ++dropped;
            }
            if (double(dropped) < kConverged[s] * double(count)) break;
        }
    }
    return ground;
}

std::vector<std::uint8_t> pyramidGround(const std::vector<core::CloudPoint>& points, const PyramidOptions& o,
                                        const std::vector<std::uint8_t>* seed) {
    const std::size_t n = points.size();
    const std::vector<std::uint8_t> low = lowOutliers(points, o.low_outlier_m);
    std::vector<std::uint8_t> control(n, 0);  // the ground the surfaces run through
    if (seed)
        for (std::size_t i = 0; i < n; ++i) control[i] = (*seed)[i] && !low[i];
    std::vector<double> cells_m;
    for (double c = o.top_cell_m; c >= o.bottom_cell_m * 0.999; c /= 2) cells_m.push_back(c);
    std::vector<double> residuals;
    for (std::size_t level = 0; level < cells_m.size(); ++level) {
        // The lowest point of each cell of this level not yet ground.
        const HeightRaster grid = HeightRaster::spanning(points, cells_m[level]);
        std::vector<std::int64_t> lowest(grid.z_m.size(), -1);
        for (std::size_t i = 0; i < n; ++i) {
            if (low[i] || control[i]) continue;
            std::int64_t& l = lowest[grid.index(grid.column(points[i].position.x), grid.row(points[i].position.y))];
            if (l < 0 || points[i].position.z < points[std::size_t(l)].position.z) l = std::int64_t(i);
        }
        if (std::find(control.begin(), control.end(), std::uint8_t(1)) == control.end()) {
            for (const std::int64_t l : lowest)
                if (l >= 0) control[std::size_t(l)] = 1;
            continue;
        }
        const double above_m = level > 0 ? cells_m[level - 1] : 2 * cells_m[level];
        const HeightRaster surface = surfaceThrough(points, control, above_m, false);
        residuals.clear();
        for (const std::int64_t l : lowest)
            if (l >= 0) {
                const glm::vec3& p = points[std::size_t(l)].position;
                residuals.push_back(p.z - surface.heightAt(p.x, p.y));
            }
        double tolerance_m = o.tolerance_m + o.tolerance_per_m * cells_m[level];
        if (o.from_residuals) {
            const double median = medianOf(residuals);
            std::vector<double> deviation;
            for (const double r : residuals) deviation.push_back(std::abs(r - median));
            tolerance_m = std::max(o.tolerance_m, median + 3 * 1.4826 * medianOf(deviation));
        }
        std::size_t k = 0;
        for (const std::int64_t l : lowest)
            if (l >= 0 && residuals[k++] <= tolerance_m) control[std::size_t(l)] = 1;
    }
    const HeightRaster surface = surfaceThrough(points, control, o.bottom_cell_m, false);
    std::vector<std::uint8_t> ground(n, 0);
    for (std::size_t i = 0; i < n; ++i) {
        if (seed && (*seed)[i]) {
            ground[i] = 1;
            continue;
        }
        const glm::vec3& p = points[i].position;
        ground[i] = !low[i] &&
                    std::abs(p.z - surface.heightAt(p.x, p.y)) <= o.threshold_m + o.scalar * surface.slopeAt(p.x, p.y);
    }
    return ground;
}

namespace {

// One variant scored: its label and what it does to a sample's points, given SMRF's answer.
struct Variant {
    std::string name;
    std::function<std::vector<std::uint8_t>(const std::vector<core::CloudPoint>&, const std::vector<std::uint8_t>&)>
        labels;
};

std::vector<Variant> variants() {
    std::vector<Variant> v;
    const auto mcc_with = [](MccOptions o, bool on_smrf) {
        return [o, on_smrf](const std::vector<core::CloudPoint>& points, const std::vector<std::uint8_t>& smrf) {
            return mccGround(points, o, on_smrf ? &smrf : nullptr);
        };
    };
    const auto mcc = [](double scale_m, double tolerance_m, bool on_smrf, double min_slope) {
        MccOptions o;
        o.scale_m = scale_m, o.tolerance_m = tolerance_m, o.min_slope = min_slope;
        return [o, on_smrf](const std::vector<core::CloudPoint>& points, const std::vector<std::uint8_t>& smrf) {
            return mccGround(points, o, on_smrf ? &smrf : nullptr);
        };
    };
    const auto pyramid = [](PyramidOptions o, bool on_smrf) {
        return [o, on_smrf](const std::vector<core::CloudPoint>& points, const std::vector<std::uint8_t>& smrf) {
            return pyramidGround(points, o, on_smrf ? &smrf : nullptr);
        };
    };
    // MCC: the paper's tolerance 0.3 m, lambda the point spacing (1 m) first, then around.
    v.push_back({"MCC, lambda 1 m, tolerance 0.3 m (+0.1 per scale)", mcc(1.0, 0.3, false, 0)});
    v.push_back({"MCC, lambda 1.5 m, tolerance 0.3 m", mcc(1.5, 0.3, false, 0)});
    v.push_back({"MCC, lambda 2 m, tolerance 0.3 m", mcc(2.0, 0.3, false, 0)});
    v.push_back({"MCC, lambda 1 m, tolerance 0.2 m", mcc(1.0, 0.2, false, 0)});
    v.push_back({"MCC, lambda 1 m, tolerance 0.5 m", mcc(1.0, 0.5, false, 0)});
    // The pyramid: 32 m down to 1 m, 0.3 m + 0.05 x the cell first, then around.
    v.push_back({"pyramid 32-1 m, tolerance 0.3 m + 0.05 x cell", pyramid(PyramidOptions{}, false)});
    {
        PyramidOptions o;
        o.tolerance_per_m = 0.025;
        v.push_back({"pyramid 32-1 m, tolerance 0.3 m + 0.025 x cell", pyramid(o, false)});
        o.tolerance_per_m = 0.1;
        v.push_back({"pyramid 32-1 m, tolerance 0.3 m + 0.1 x cell", pyramid(o, false)});
        o.tolerance_per_m = 0.15;
        v.push_back({"pyramid 32-1 m, tolerance 0.3 m + 0.15 x cell (SMRF's slope)", pyramid(o, false)});
        o = PyramidOptions{};
        o.top_cell_m = 64;
        v.push_back({"pyramid 64-1 m, tolerance 0.3 m + 0.05 x cell", pyramid(o, false)});
        o = PyramidOptions{};
        o.from_residuals = true;
        v.push_back(
            {"pyramid 32-1 m, tolerance from the residuals (median + 3 robust sigmas, >= 0.3 m)", pyramid(o, false)});
    }
    // On SMRF's answer: MCC takes points off its ground, the pyramid gives ground back.
    v.push_back({"SMRF, then MCC's test on its ground (lambda 1 m, tolerance 0.3 m)", mcc(1.0, 0.3, true, 0)});
    v.push_back({"SMRF, then MCC's test on its ground (lambda 1 m, tolerance 0.5 m)", mcc(1.0, 0.5, true, 0)});
    v.push_back({"SMRF, then MCC's test on its ground where steeper than 0.2 (lambda 1 m, tolerance 0.3 m)",
                 mcc(1.0, 0.3, true, 0.2)});
    {
        MccOptions o;
        o.max_slope = 0.1;
        v.push_back({"SMRF, then MCC's test on its ground where gentler than 0.1 (lambda 1 m, tolerance 0.3 m)",
                     mcc_with(o, true)});
        o = MccOptions{};
        o.max_iterations = 1;
        v.push_back(
            {"SMRF, then MCC's test on its ground, once per scale (lambda 1 m, tolerance 0.3 m)", mcc_with(o, true)});
    }
    {
        PyramidOptions o;
        o.top_cell_m = 4;
        v.push_back(
            {"SMRF, ground given back by the pyramid on its ground (4-1 m, 0.3 m + 0.05 x cell)", pyramid(o, true)});
        o.tolerance_m = 0.15, o.tolerance_per_m = 0, o.threshold_m = 0.3, o.scalar = 0.5;
        v.push_back({"SMRF, ground given back by the pyramid on its ground (4-1 m, 0.15 m; final 0.3 m + 0.5 x slope)",
                     pyramid(o, true)});
    }
    {
        MccOptions m;
        m.max_slope = 0.1;
        PyramidOptions p;
        p.top_cell_m = 4, p.tolerance_m = 0.15, p.tolerance_per_m = 0, p.threshold_m = 0.3, p.scalar = 0.5;
        v.push_back({"SMRF, MCC's test where gentler than 0.1, then ground given back by the pyramid (both as above)",
                     [m, p](const std::vector<core::CloudPoint>& points, const std::vector<std::uint8_t>& smrf) {
                         const std::vector<std::uint8_t> fewer = mccGround(points, m, &smrf);
                         return pyramidGround(points, p, &fewer);
                     }});
    }
    {
        MccOptions o;
        v.push_back({"SMRF's ground or MCC's (lambda 1 m, tolerance 0.3 m)",
                     [o](const std::vector<core::CloudPoint>& points, const std::vector<std::uint8_t>& smrf) {
                         std::vector<std::uint8_t> g = mccGround(points, o);
                         for (std::size_t i = 0; i < g.size(); ++i) g[i] = g[i] || smrf[i];
                         return g;
                     }});
    }
    return v;
}

void printRow(const std::string& what, const std::vector<AdaptiveSample>& samples, const std::vector<Counts>& c) {
    const Counts m = meanOf(c);
    std::printf("| %s | %.2f | %.2f | %.2f | %.1f | %s |", what.c_str(), m.type1, m.type2, m.total, m.kappa,
                pastCsf(samples, c).c_str());
    for (const Counts& x : c) std::printf(" %.2f |", x.total);
    std::printf("\n");
    std::fflush(stdout);
}

Counts scoreLabels(const AdaptiveSample& s, const std::vector<std::uint8_t>& found) {
    Confusion c;
    for (std::size_t i = 0; i < found.size(); ++i) c.add((*s.truth)[i] != 0, found[i] != 0);
    return countsOf(c);
}

}  // namespace

void runMultiscale(const std::vector<AdaptiveSample>& samples) {
    std::vector<std::vector<std::uint8_t>> smrf;
    std::vector<Counts> base;
    for (const AdaptiveSample& s : samples) {
        smrf.push_back(sim::classifyGround(*s.points, sim::GroundFileOptions{}));
        base.push_back(scoreLabels(s, smrf.back()));
    }
    std::printf(
        "\nMultiscale surface filters (prototypes; one parameter set per row for all samples), beside "
        "`ladarvr ground`. Percent; per sample the total error.\n\n"
        "| variant | mean type I | mean type II | mean total error | mean kappa | samples past CSF + 1 |");
    for (const AdaptiveSample& s : samples) std::printf(" %s |", s.name.c_str());
    std::printf("\n|---|---:|---:|---:|---:|---|");
    for (std::size_t k = 0; k < samples.size(); ++k) std::printf("---:|");
    std::printf("\n");
    printRow("`ladarvr ground` (SMRF)", samples, base);
    for (const Variant& v : variants()) {
        const auto t0 = Clock::now();
        std::vector<Counts> c;
        for (std::size_t k = 0; k < samples.size(); ++k)
            c.push_back(scoreLabels(samples[k], v.labels(*samples[k].points, smrf[k])));
        printRow(v.name, samples, c);
        std::fprintf(stderr, "bench ground-isprs --multiscale: %s: %.1f s\n", v.name.c_str(), secondsSince(t0));
    }
    double csf_mean = 0;
    for (const AdaptiveSample& s : samples) csf_mean += csfPublishedTotal(s.name) / double(samples.size());
    std::printf("| CSF published | | | %.2f | | |", csf_mean);
    for (const AdaptiveSample& s : samples) std::printf(" %.2f |", csfPublishedTotal(s.name));
    std::printf("\n");
}

}  // namespace bench
