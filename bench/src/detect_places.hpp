// bench/src/detect_places.hpp: what the families run (detect_families.cpp) needs beyond
// the synthetic scenes: real places as clutter (the ISPRS test sites of tests/data/real
// turned into scenes by sim::buildSceneFromCloud, the vehicles moved on their ground), and
// the detector across point densities (evaluation clouds thinned, the density measured on
// the target's area, outcomes gathered per density band).
#pragma once
#include "detect_trained.hpp"

#include <core/point_cloud.hpp>

#include <nlohmann/json.hpp>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace bench {

/// A real survey made a scene: its name, the survey and the scene folder.
struct RealPlace {
    std::string name;                 // "CSite2", ...
    std::filesystem::path survey;     // tests/data/real/<name>_orig-utm.laz
    std::filesystem::path scene;      // <dir>/scene.json once made
    double survey_points_per_m2 = 0;  // the survey's own density over the 2 m cells it covers
};

/// Makes the scene of tests/data/real/<name>_orig-utm.laz in `dir` (sim::buildSceneFromCloud:
/// its ground by the filter, its other points as boxes of `voxel_m`, `vehicle` on a flat
/// free spot drawn with `seed`), unless `dir`/scene.json is already there (a kept --tmp
/// folder), and measures the survey's density. Throws core::Error("bench detect: ...").
RealPlace makeRealPlace(const std::string& name, const std::filesystem::path& dir, const std::filesystem::path& vehicle,
                        double voxel_m, std::uint64_t seed);

/// A corpus SPEC of `scene` (a scene.json) whose target is one of `files`, moved up to
/// `reach_m` and turned, seen from orbits 200 to 300 m up by the ideal sensor or a
/// preset; with `densities` (training), from 100 to 300 m and with 64 or 128 rays across.
nlohmann::json vehicleSpec(const std::string& scene, const std::vector<std::string>& files, int count,
                           std::uint64_t seed, int views, bool densities, int reach_m);

/// A corpus SPEC on a real place: `placement` "triangles" (only the boxes near the target
/// block it), the target one of `files`, moved up to `reach_m` and turned, seen from
/// orbits 200 to 300 m up by the ideal sensor or a preset; with `densities` (training), from
/// 100 to 300 m and with 64 or 128 rays across.
nlohmann::json placeSpec(const RealPlace& place, const std::vector<std::string>& files, int count, std::uint64_t seed,
                         int views, bool densities, int reach_m);

/// `c` with each point kept with probability `keep` (a hash of `seed` and its index: the
/// same arguments keep the same points). keep >= 1 returns a copy.
core::PointCloud thinCloud(const core::PointCloud& c, double keep, std::uint64_t seed);

/// The area of the target's footprint: the convex hull of the target-labelled points'
/// x, y, in m² (0 with fewer than 3 of them).
double targetAreaM2(const core::PointCloud& c);

/// Target-labelled points of `c`.
std::size_t targetPoints(const core::PointCloud& c);

/// The density bands the table reports, by measured points/m² on the target's area.
std::size_t densityBand(double points_per_m2);
const std::vector<std::string>& densityBandNames();

/// One detector's outcomes per density band.
using BandOutcomes = std::vector<std::vector<Outcome>>;

}  // namespace bench
