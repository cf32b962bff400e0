// bench/src/detect_places.cpp: real places as clutter and the detector across point
// densities, for the families run (detect_places.hpp). A real place is an ISPRS test site
// (tests/data/real, about 1-2 points/m²) made a scene the way `ladarvr scene from-cloud`
// makes it: its ground a terrain mesh, its buildings, trees and cars voxel boxes; the
// corpus then moves each vehicle on that ground among the boxes ("placement":
// "triangles"). Densities: an evaluation cloud thinned at random keeps its labels, so the
// same target is ranked at fewer points/m²; the density is measured on the target's own
// footprint (the hull of its points in the full cloud), not taken from the sensor's
// nominal figures.
#include "detect_places.hpp"

#include "common.hpp"

#include <core/error.hpp>
#include <core/random.hpp>
#include <io/cloud_io.hpp>
#include <sim/scene_from_cloud.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <unordered_set>

namespace bench {
namespace {

namespace fs = std::filesystem;

// The survey's points over the area of the 2 m cells holding at least one of them: its
// density where it has points (a site's bounds hold empty corners).
double surveyDensity(const fs::path& survey) {
    const core::PointCloud c = io::readCloud(survey);
    constexpr double kCell_m = 2.0;
    std::unordered_set<std::uint64_t> cells;
    for (const core::CloudPoint& p : c.points) {
        const auto i = std::uint64_t(std::uint32_t(std::int32_t(std::floor(p.position.x / kCell_m))));
        const auto j = std::uint64_t(std::uint32_t(std::int32_t(std::floor(p.position.y / kCell_m))));
        cells.insert((i << 32) | j);
    }
    return cells.empty() ? 0.0 : double(c.points.size()) / (double(cells.size()) * kCell_m * kCell_m);
}

double cross(const glm::dvec2& o, const glm::dvec2& a, const glm::dvec2& b) {
    return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
}

}  // namespace

RealPlace makeRealPlace(const std::string& name, const fs::path& dir, const fs::path& vehicle, double voxel_m,
                        std::uint64_t seed) {
    RealPlace place{name, sourceRoot() / "tests" / "data" / "real" / (name + "_orig-utm.laz"), dir / "scene.json", 0};
    if (!fs::exists(place.survey))
        throw core::Error("bench detect: real place " + name + ": " + place.survey.string() + " does not exist");
    place.survey_points_per_m2 = surveyDensity(place.survey);
    if (fs::exists(place.scene)) return place;  // made by an earlier run into the same --tmp
    sim::SceneFromCloudOptions o;
    o.voxel_m = voxel_m;
    o.coarsen = true;
    o.vehicle.mesh = vehicle;
    o.vehicle.seed = seed;
    sim::validate(o);
    std::fprintf(stderr, "bench detect: real place %s: scene from %s\n", name.c_str(), place.survey.c_str());
    const sim::SceneFromCloud s = sim::buildSceneFromCloud(place.survey, o, [](std::size_t) {});
    sim::writeSceneFolder(dir, s, o);
    std::fprintf(stderr, "bench detect: real place %s: %zu points, %zu ground, %zu boxes of %g m\n", name.c_str(),
                 s.points, s.ground_points, s.boxes.size(), s.voxel_m);
    return place;
}

nlohmann::json vehicleSpec(const std::string& scene, const std::vector<std::string>& files, int count,
                           std::uint64_t seed, int views, bool densities, int reach_m) {
    nlohmann::json spec = {{"scene", scene},
                           {"count", count},
                           {"seed", seed},
                           {"vary",
                            {{"target_yaw_deg", {{"min", 0}, {"max", 360}}},
                             {"target_offset_m", {{"min", 0}, {"max", reach_m}}},
                             {"target_files", files},
                             {"sensor_preset", {"ideal", "riegl-vux1uav", "livox-avia"}},
                             {"altitude_m", {{"min", 200}, {"max", 300}}},
                             {"alpha_deg", {{"min", 30}, {"max", 45}}},
                             {"views", views},
                             {"resolution", 128}}}};
    // Training across densities: lower orbits (denser clouds) and a quarter of the rays
    // (sparser ones) beside the evaluation's.
    if (densities) {
        spec["vary"]["altitude_m"] = {{"min", 100}, {"max", 300}};
        spec["vary"]["resolution"] = {64, 128};
    }
    return spec;
}

nlohmann::json placeSpec(const RealPlace& place, const std::vector<std::string>& files, int count, std::uint64_t seed,
                         int views, bool densities, int reach_m) {
    nlohmann::json spec = vehicleSpec(place.scene.string(), files, count, seed, views, densities, reach_m);
    spec["placement"] = "triangles";
    return spec;
}

core::PointCloud thinCloud(const core::PointCloud& c, double keep, std::uint64_t seed) {
    core::PointCloud t = c;
    if (keep >= 1.0) return t;
    t.foreign.reset();  // the detector reads positions and labels only
    std::size_t w = 0;
    for (std::size_t i = 0; i < t.points.size(); ++i)
        if (core::unitHalfOpen(core::mix64(seed * core::kGolden + i)) < keep) t.points[w++] = t.points[i];
    t.points.resize(w);
    return t;
}

std::size_t targetPoints(const core::PointCloud& c) {
    std::size_t n = 0;
    for (const core::CloudPoint& p : c.points) n += p.label == core::Role::Target;
    return n;
}

double targetAreaM2(const core::PointCloud& c) {
    // Andrew's monotone chain over the target points' x, y.
    std::vector<glm::dvec2> pts;
    for (const core::CloudPoint& p : c.points)
        if (p.label == core::Role::Target) pts.emplace_back(p.position.x, p.position.y);
    if (pts.size() < 3) return 0.0;
    std::sort(pts.begin(), pts.end(),
              [](const glm::dvec2& a, const glm::dvec2& b) { return a.x < b.x || (a.x == b.x && a.y < b.y); });
    std::vector<glm::dvec2> hull(2 * pts.size());
    std::size_t k = 0;
    for (std::size_t i = 0; i < pts.size(); ++i) {
        while (k >= 2 && cross(hull[k - 2], hull[k - 1], pts[i]) <= 0) --k;
        hull[k++] = pts[i];
    }
    for (std::size_t i = pts.size() - 1, lower = k + 1; i > 0; --i) {
        while (k >= lower && cross(hull[k - 2], hull[k - 1], pts[i - 1]) <= 0) --k;
        hull[k++] = pts[i - 1];
    }
    double area = 0.0;
    for (std::size_t i = 0; i + 1 < k; ++i) area += hull[i].x * hull[i + 1].y - hull[i + 1].x * hull[i].y;
    return std::abs(area) / 2.0;
}

const std::vector<std::string>& densityBandNames() {
    static const std::vector<std::string> names = {"under 3", "3-10",      "10-30",         "30-100",
                                                   "100-300", "300-1,000", "1,000 and more"};
    return names;
}

std::size_t densityBand(double points_per_m2) {
    constexpr double kEdges[] = {3, 10, 30, 100, 300, 1000};
    std::size_t b = 0;
    while (b < std::size(kEdges) && points_per_m2 >= kEdges[b]) ++b;
    return b;
}

}  // namespace bench
