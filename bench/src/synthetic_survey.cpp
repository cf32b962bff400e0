// bench/src/synthetic_survey.cpp: see synthetic_survey.hpp.
#include "synthetic_survey.hpp"

#include "common.hpp"

#include <core/error.hpp>
#include <core/roles.hpp>
#include <io/copc_writer.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <map>
#include <vector>

namespace bench {
namespace {

constexpr int kGrid = 128;  // cells across a node's footprint
constexpr std::size_t kCells = std::size_t(kGrid) * kGrid;

// A hash of a cell and a draw, uniform in [0, 1).
double unit(std::uint64_t a, std::uint64_t b, std::uint64_t draw) {
    std::uint64_t h = a * 0x9E3779B97F4A7C15ull ^ (b + 0x632BE59BD9B4E019ull) * 0xC2B2AE3D27D4EB4Full ^ draw;
    h ^= h >> 31;
    h *= 0xBF58476D1CE4E5B9ull;
    h ^= h >> 29;
    h *= 0x94D049BB133111EBull;
    h ^= h >> 32;
    return double(h >> 11) * (1.0 / 9007199254740992.0);
}

// The surface at (x, y), metres from the cube's centre: hills and, on a grid of blocks,
// flat roofs 6-14 m up.
double surface_m(double x, double y, bool& roof) {
    const double ground = 4.0 + 3.0 * std::sin(x / 97.0) * std::cos(y / 71.0) + 0.8 * std::sin(x / 13.0 + y / 17.0);
    const double bx = x - 60.0 * std::floor(x / 60.0), by = y - 45.0 * std::floor(y / 45.0);
    roof = bx < 14.0 && by < 11.0 && std::abs(x) > 40.0;  // the middle stays open ground
    if (!roof) return ground;
    return ground + 6.0 +
           8.0 * unit(std::uint64_t(std::floor(x / 60.0) + 1e6), std::uint64_t(std::floor(y / 45.0) + 1e6), 7);
}

}  // namespace

SyntheticSurvey writeSyntheticSurvey(const std::filesystem::path& path, std::size_t points, const glm::dvec3& origin,
                                     int bits, int threads) {
    if (points == 0) throw core::Error("bench view: a synthetic survey of 0 points");
    // The leaf level: the deepest whose one point a cell does not exceed the count.
    int leaf = 0;
    while (leaf < 12 && double(kCells) * std::pow(4.0, leaf + 1) <= double(points)) ++leaf;
    double upper = 0.0;
    for (int d = 0; d < leaf; ++d) upper += double(kCells) * std::pow(4.0, d);
    const double per_leaf_cell = std::max(1.0, (double(points) - upper) / (double(kCells) * std::pow(4.0, leaf)));
    core::CloudFields fields;  // x y z rgb label view range
    io::LasOptions las;
    las.threads = std::max(threads - 1, 0);
    io::CopcNodeWriter writer(path, origin, fields, bits, las);
    const double edge_m = std::ldexp(0.001, bits);
    const double corner_m = -0.001 * std::ldexp(1.0, bits - 1) - 0.0005;  // the cube's low face, local
    SyntheticSurvey out;
    out.leaf_level = leaf;
    const Clock::time_point t0 = Clock::now();
    double last_report = 0.0;
    for (int d = 0; d <= leaf; ++d) {
        const int side = 1 << d;
        const double node_m = edge_m / side, cell_m = node_m / kGrid;
        // Nodes of one footprint row at a time: at most `side` footprints, one node per z cell.
        for (int ky = 0; ky < side; ++ky) {
            std::map<std::array<int, 3>, std::vector<core::CloudPoint>> nodes;
            std::array<int, 3> last_key{-1, -1, -1};
            std::vector<core::CloudPoint>* last = nullptr;
            for (int kx = 0; kx < side; ++kx) {
                const double x0 = corner_m + kx * node_m, y0 = corner_m + ky * node_m;
                for (int j = 0; j < kGrid; ++j)
                    for (int i = 0; i < kGrid; ++i) {
                        const std::uint64_t cx = std::uint64_t(kx) * kGrid + std::uint64_t(i),
                                            cy = std::uint64_t(ky) * kGrid + std::uint64_t(j);
                        const std::uint64_t cell = (std::uint64_t(d) << 56) ^ (cy << 28) ^ cx;
                        int n = 1;
                        if (d == leaf) {
                            n = int(per_leaf_cell);
                            if (unit(cell, 1, 99) < per_leaf_cell - n) ++n;
                        }
                        for (int k = 0; k < n; ++k) {
                            // Kept 2 % of a cell off its sides: clear of the millimetre rounding.
                            const double x = x0 + (i + 0.02 + 0.96 * unit(cell, k, 1)) * cell_m;
                            const double y = y0 + (j + 0.02 + 0.96 * unit(cell, k, 2)) * cell_m;
                            bool roof = false;
                            const double z = surface_m(x, y, roof) + 0.02 * (unit(cell, k, 3) - 0.5);
                            core::CloudPoint p;
                            p.position = glm::vec3(float(x), float(y), float(z));
                            const auto shade = std::uint8_t(std::clamp(40.0 + z * 12.0, 0.0, 255.0));
                            p.rgb = roof ? core::packRgb(shade, std::uint8_t(shade / 2), std::uint8_t(shade / 3))
                                         : core::packRgb(std::uint8_t(shade / 3), shade, std::uint8_t(shade / 3));
                            p.label = roof ? core::Role::Environment : core::Role::Ground;
                            p.view = std::uint16_t((kx + ky) % 100);
                            p.range_m = float(300.0 + 0.1 * z);
                            // The node: by the integer coordinates, as the file holds them.
                            std::array<int, 3> key{};
                            const float local[3] = {p.position.x, p.position.y, p.position.z};
                            for (std::size_t a = 0; a < 3; ++a) {
                                const auto mm = std::int64_t(std::llround(double(local[a]) / 0.001));
                                key[a] = int((mm + (std::int64_t(1) << (bits - 1))) >> (bits - d));
                            }
                            if (key[0] != kx || key[1] != ky)
                                throw core::Error("bench view: synthetic survey: a point left its footprint");
                            if (!last || key != last_key) {
                                last = &nodes[key];
                                last_key = key;
                            }
                            last->push_back(p);
                        }
                    }
            }
            std::vector<io::CopcNodeWriter::Node> batch;
            for (auto& [k, pts] : nodes) {
                batch.push_back({io::CopcKey{d, k[0], k[1], k[2]}, pts});
                out.points += pts.size();
                ++out.nodes;
            }
            writer.add(batch);
            const double s = secondsSince(t0);
            if (s - last_report >= 10.0) {
                last_report = s;
                std::fprintf(stderr, "bench view: synthetic survey: level %d of %d, %zu points, %.0f s\n", d, leaf,
                             out.points, s);
            }
        }
    }
    writer.commit();
    return out;
}

}  // namespace bench
