// detect/src/segment_features.cpp: the per-segment features of detect/segment_features.hpp.
#include <detect/segment_features.hpp>

#include <detect/cluster_detector.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

namespace detect {
namespace {

constexpr float kMissing = std::numeric_limits<float>::quiet_NaN();

// Eigenvalues (descending) and eigenvectors (columns, same order) of a symmetric 3x3
// matrix by cyclic Jacobi rotations: a fixed sequence of operations, so the result is
// the same on every run.
void symmetricEigen(double a[3][3], double values[3], double vectors[3][3]) {
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) vectors[i][j] = i == j ? 1.0 : 0.0;
    for (int sweep = 0; sweep < 50; ++sweep) {
        const double off = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
        if (off < 1e-30) break;
        for (int p = 0; p < 2; ++p)
            for (int q = p + 1; q < 3; ++q) {
                if (std::abs(a[p][q]) < 1e-300) continue;
                const double theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
                const double t = (theta >= 0 ? 1.0 : -1.0) / (std::abs(theta) + std::sqrt(theta * theta + 1.0));
                const double c = 1.0 / std::sqrt(t * t + 1.0), s = t * c;
                for (int k = 0; k < 3; ++k) {  // A <- A J
                    const double akp = a[k][p], akq = a[k][q];
                    a[k][p] = c * akp - s * akq;
                    a[k][q] = s * akp + c * akq;
                }
                for (int k = 0; k < 3; ++k) {  // A <- J^T A
                    const double apk = a[p][k], aqk = a[q][k];
                    a[p][k] = c * apk - s * aqk;
                    a[q][k] = s * apk + c * aqk;
                }
                for (int k = 0; k < 3; ++k) {
                    const double vkp = vectors[k][p], vkq = vectors[k][q];
                    vectors[k][p] = c * vkp - s * vkq;
                    vectors[k][q] = s * vkp + c * vkq;
                }
            }
    }
    int order[3] = {0, 1, 2};
    std::sort(order, order + 3, [&](int x, int y) { return a[x][x] > a[y][y]; });
    double v[3][3];
    for (int k = 0; k < 3; ++k) {
        values[k] = std::max(0.0, a[order[k]][order[k]]);
        for (int i = 0; i < 3; ++i) v[i][k] = vectors[i][order[k]];
    }
    for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k) vectors[i][k] = v[i][k];
}

double quantile(std::vector<double>& x, double q) {
    const std::size_t k = std::min(x.size() - 1, std::size_t(q * double(x.size() - 1) + 0.5));
    std::nth_element(x.begin(), x.begin() + std::ptrdiff_t(k), x.end());
    return x[k];
}

// kV2's features, appended to `f`: what a vehicle's shape has whatever its size (see
// segment_features.hpp). `hag` holds the points' heights above the terrain, in the order
// of `points`; `box` is the segment's oriented box.
void shapeFeatures(const core::PointCloud& cloud, std::span<const std::uint32_t> points, const std::vector<double>& hag,
                   const OrientedBox& box, double density_m2, std::vector<float>& f) {
    const double n = double(points.size());
    const double length = std::max(box.size_m.x, 1e-3), width = std::max(box.size_m.y, 1e-3),
                 height = std::max(box.size_m.z, 1e-3);
    const auto [lo_it, hi_it] = std::minmax_element(hag.begin(), hag.end());
    const double hag_min = *lo_it, hag_max = std::max(*hi_it, 1e-3);
    f.push_back(float(width / length));
    f.push_back(float(height / length));
    f.push_back(float(height / width));
    f.push_back(float(hag_max / length));
    std::vector<double> sorted = hag;
    f.push_back(float(quantile(sorted, 0.1) / hag_max));
    f.push_back(float(quantile(sorted, 0.5) / hag_max));
    f.push_back(float(quantile(sorted, 0.9) / hag_max));
    f.push_back(float(std::max(0.0, hag_min) / hag_max));

    // Each point's place in the box: u along the length, v across, both in [0, 1).
    const double a = box.yaw_deg * 3.14159265358979323846 / 180.0, c = std::cos(a), s = std::sin(a);
    constexpr int kLong = 5, kCross = 3, kGridU = 8, kGridV = 4;
    double long_top[kLong] = {}, cross_top[kCross] = {};
    bool grid[kGridU][kGridV] = {}, grid_top[kGridU][kGridV] = {};
    double top_sum = 0, top_sum2 = 0;
    std::size_t top_n = 0, side = 0, end = 0, mid = 0;
    for (std::size_t k = 0; k < points.size(); ++k) {
        const glm::dvec3 p = glm::dvec3(cloud.points[points[k]].position) - box.centre;
        const double u = std::clamp((c * p.x + s * p.y) / length + 0.5, 0.0, 0.999999),
                     v = std::clamp((-s * p.x + c * p.y) / width + 0.5, 0.0, 0.999999);
        const double h = hag[k] / hag_max;
        long_top[int(u * kLong)] = std::max(long_top[int(u * kLong)], h);
        cross_top[int(v * kCross)] = std::max(cross_top[int(v * kCross)], h);
        grid[int(u * kGridU)][int(v * kGridV)] = true;
        if (h >= 0.8) {
            grid_top[int(u * kGridU)][int(v * kGridV)] = true;
            top_sum += h, top_sum2 += h * h, ++top_n;
        }
        if (h >= 0.25 && h <= 0.75) {
            ++mid;
            side += std::abs(v - 0.5) > 0.35;
            end += std::abs(u - 0.5) > 0.4;
        }
    }
    f.push_back(float((long_top[0] + long_top[kLong - 1]) / 2));
    f.push_back(float((long_top[1] + long_top[kLong - 2]) / 2));
    f.push_back(float(long_top[kLong / 2]));
    f.push_back(float(std::abs(long_top[0] - long_top[kLong - 1])));
    int empty = 0;
    for (const double t : long_top) empty += t <= 0.0;
    f.push_back(float(empty) / float(kLong));
    f.push_back(float((cross_top[0] + cross_top[kCross - 1]) / 2));
    const double top_mean = top_n ? top_sum / double(top_n) : 0.0;
    f.push_back(float(top_n ? std::sqrt(std::max(0.0, top_sum2 / double(top_n) - top_mean * top_mean)) : 0.0));
    int filled = 0, covered = 0;
    for (int u = 0; u < kGridU; ++u)
        for (int v = 0; v < kGridV; ++v) filled += grid[u][v], covered += grid_top[u][v];
    f.push_back(float(covered) / float(kGridU * kGridV));
    f.push_back(float(filled) / float(kGridU * kGridV));
    f.push_back(mid ? float(double(side) / double(mid)) : 0.0f);
    f.push_back(mid ? float(double(end) / double(mid)) : 0.0f);
    if (density_m2 > 0) {
        f.push_back(float(std::log(n / density_m2)));
        f.push_back(float(n / std::max(length * width, 0.01) / density_m2));
    } else {
        f.push_back(kMissing);
        f.push_back(kMissing);
    }
}

}  // namespace

const std::vector<std::string>& segmentFeatureNames(FeatureSet set) {
    static const std::vector<std::string> v1 = {
        "log_points",
        "length_m",
        "width_m",
        "height_m",
        "size_match",
        "hag_max_m",
        "hag_min_m",
        "hag_mean_m",
        "hag_p10_m",
        "hag_p50_m",
        "hag_p90_m",
        "eigen_1",
        "eigen_2",
        "eigen_3",
        "linearity",
        "planarity",
        "scattering",
        "normal_z",
        "principal_z",
        "points_per_m2",
        "points_per_m3",
        "profile_q1",
        "profile_q2",
        "profile_q3",
        "profile_q4",
        "top_fraction",
        "footprint_fill",
        "multi_return_fraction",
        "last_return_fraction",
        "intensity_mean",
        "intensity_std",
    };
    static const std::vector<std::string> v2 = [] {
        std::vector<std::string> n = v1;
        for (const char* extra :
             {"width_over_length",  "height_over_length",  "height_over_width",   "hag_max_over_length",
              "rel_hag_p10",        "rel_hag_p50",         "rel_hag_p90",         "gap_under_share",
              "long_profile_ends",  "long_profile_next",   "long_profile_centre", "long_profile_asymmetry",
              "long_profile_empty", "cross_profile_sides", "top_spread",          "top_cover",
              "box_grid_fill",      "side_wall_share",     "end_wall_share",      "log_points_rel",
              "points_per_m2_rel"})
            n.push_back(extra);
        return n;
    }();
    return set == FeatureSet::kV1 ? v1 : v2;
}

std::optional<FeatureSet> featureSetOf(const std::vector<std::string>& names) {
    for (const FeatureSet set : {FeatureSet::kV1, FeatureSet::kV2})
        if (names == segmentFeatureNames(set)) return set;
    return std::nullopt;
}

std::vector<float> segmentFeatures(const core::PointCloud& cloud, std::span<const std::uint32_t> points,
                                   std::span<const float> height_m, const glm::dvec3& target_size_m, FeatureSet set,
                                   double density_m2) {
    std::vector<float> f;
    f.reserve(segmentFeatureNames(set).size());
    const double n = double(points.size());
    const std::vector<std::uint32_t> list(points.begin(), points.end());
    const OrientedBox box = fitBox(cloud, list, 0.01);
    const double length = box.size_m.x, width = box.size_m.y, height = box.size_m.z;
    f.push_back(float(std::log(n)));
    f.push_back(float(length));
    f.push_back(float(width));
    f.push_back(float(height));
    f.push_back(float(sizeScore(box.size_m, target_size_m, 1.5)));

    // Height above the terrain.
    std::vector<double> hag(points.size());
    double hag_sum = 0;
    for (std::size_t k = 0; k < points.size(); ++k) {
        hag[k] = double(height_m[points[k]]);
        hag_sum += hag[k];
    }
    const auto [hmin_it, hmax_it] = std::minmax_element(hag.begin(), hag.end());
    const double hag_min = *hmin_it, hag_max = *hmax_it;
    f.push_back(float(hag_max));
    f.push_back(float(hag_min));
    f.push_back(float(hag_sum / n));
    std::vector<double> sorted = hag;
    f.push_back(float(quantile(sorted, 0.1)));
    f.push_back(float(quantile(sorted, 0.5)));
    f.push_back(float(quantile(sorted, 0.9)));

    // 3D PCA about the centroid (moments relative to the first point, in double).
    const glm::dvec3 ref = glm::dvec3(cloud.points[points.front()].position);
    glm::dvec3 mean{0.0};
    for (const std::uint32_t i : points) mean += glm::dvec3(cloud.points[i].position) - ref;
    mean /= n;
    double cov[3][3] = {};
    for (const std::uint32_t i : points) {
        const glm::dvec3 d = glm::dvec3(cloud.points[i].position) - ref - mean;
        for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b) cov[a][b] += d[a] * d[b];
    }
    for (auto& row : cov)
        for (double& v : row) v /= n;
    double ev[3], evec[3][3];
    symmetricEigen(cov, ev, evec);
    const double sum = ev[0] + ev[1] + ev[2];
    for (int k = 0; k < 3; ++k) f.push_back(float(sum > 0 ? ev[k] / sum : 0.0));
    const double l1 = std::max(ev[0], 1e-12);
    f.push_back(float((ev[0] - ev[1]) / l1));
    f.push_back(float((ev[1] - ev[2]) / l1));
    f.push_back(float(ev[2] / l1));
    f.push_back(float(std::abs(evec[2][2])));  // z of the smallest axis: 1 for a roof, 0 for a wall
    f.push_back(float(std::abs(evec[2][0])));  // z of the largest axis: 1 for a pole or trunk

    // Density over the box's footprint and volume.
    f.push_back(float(n / std::max(length * width, 0.01)));
    f.push_back(float(n / std::max(length * width * height, 0.01)));

    // Vertical profile: the share of points in each quarter of the segment's height range,
    // and the share within 0.3 m of its top (a roof, a turret).
    double profile[4] = {0, 0, 0, 0};
    std::size_t top = 0;
    const double range = std::max(hag_max - hag_min, 1e-6);
    for (const double h : hag) {
        profile[std::min(3, int(4.0 * (h - hag_min) / range))] += 1.0;
        top += h >= hag_max - 0.3;
    }
    for (const double p : profile) f.push_back(float(p / n));
    f.push_back(float(double(top) / n));

    // Footprint fill: occupied 0.5 m cells over the cells of the box's footprint.
    {
        const double c = std::cos(box.yaw_deg * 3.14159265358979323846 / 180.0),
                     s = std::sin(box.yaw_deg * 3.14159265358979323846 / 180.0);
        // Each point's cell; the occupied ones counted on a bitmap over the cells' range
        // when it is at most a few bits a point (always, unless a few points lie far out),
        // else as packed keys sorted and deduplicated (a set of pairs costs a node per point).
        const auto cellOf = [&](std::uint32_t i) {
            const glm::dvec3 p = glm::dvec3(cloud.points[i].position) - box.centre;
            return std::pair<std::int64_t, std::int64_t>{std::int64_t(std::floor((c * p.x + s * p.y) / 0.5)),
                                                         std::int64_t(std::floor((-s * p.x + c * p.y) / 0.5))};
        };
        std::int64_t u0 = INT64_MAX, u1 = INT64_MIN, v0 = INT64_MAX, v1 = INT64_MIN;
        for (const std::uint32_t i : points) {
            const auto [u, v] = cellOf(i);
            u0 = std::min(u0, u), u1 = std::max(u1, u), v0 = std::min(v0, v), v1 = std::max(v1, v);
        }
        std::size_t occupied = 0;
        const double range_cells = (double(u1) - double(u0) + 1.0) * (double(v1) - double(v0) + 1.0);
        if (range_cells <= std::max(65536.0, 16.0 * n)) {
            const std::size_t su = std::size_t(u1 - u0 + 1);
            std::vector<bool> seen(std::size_t(range_cells), false);
            for (const std::uint32_t i : points) {
                const auto [u, v] = cellOf(i);
                const std::size_t bit = std::size_t(v - v0) * su + std::size_t(u - u0);
                occupied += !seen[bit];
                seen[bit] = true;
            }
        } else {
            std::vector<std::uint64_t> cells;
            cells.reserve(points.size());
            for (const std::uint32_t i : points) {
                const auto [u, v] = cellOf(i);
                cells.push_back((std::uint64_t(u + (std::int64_t(1) << 31)) << 32) |
                                std::uint64_t(v + (std::int64_t(1) << 31)));
            }
            std::sort(cells.begin(), cells.end());
            occupied = std::size_t(std::unique(cells.begin(), cells.end()) - cells.begin());
        }
        const double footprint = std::max(1.0, std::ceil(length / 0.5) * std::ceil(width / 0.5));
        f.push_back(float(std::min(1.0, double(occupied) / footprint)));
    }

    // Returns and intensity, when the cloud has them.
    if (cloud.fields.returns) {
        std::size_t multi = 0, last = 0;
        for (const std::uint32_t i : points) {
            multi += cloud.points[i].returns > 1;
            last += cloud.points[i].return_number == cloud.points[i].returns;
        }
        f.push_back(float(double(multi) / n));
        f.push_back(float(double(last) / n));
    } else {
        f.push_back(kMissing);
        f.push_back(kMissing);
    }
    if (cloud.fields.intensity) {
        double s1 = 0, s2 = 0;
        for (const std::uint32_t i : points) {
            const double v = double(cloud.points[i].intensity) / 65535.0;
            s1 += v;
            s2 += v * v;
        }
        const double m = s1 / n;
        f.push_back(float(m));
        f.push_back(float(std::sqrt(std::max(0.0, s2 / n - m * m))));
    } else {
        f.push_back(kMissing);
        f.push_back(kMissing);
    }
    if (set != FeatureSet::kV1) shapeFeatures(cloud, points, hag, box, density_m2, f);
    return f;
}

}  // namespace detect
