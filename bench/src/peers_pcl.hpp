// bench/src/peers_pcl.hpp: the PCL side of `ladarvr bench peers`, behind an interface
// free of PCL types so that PCL's headers stay in peers_pcl.cpp alone.
#pragma once
#include <core/point_cloud.hpp>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <vector>

namespace bench::peers {

/// Times (seconds, one run each) of PCL's savePCDFileBinary and loadPCDFile on `cloud`'s
/// points as a PCL point type with our exact fields (x y z rgb label view range).
struct PclIo {
    double write_s = 0.0, read_s = 0.0;
    std::size_t points_read = 0;
    bool same_points = false;  // what PCL read back equals `cloud` field by field
};
/// Writes `path` with pcl::io::savePCDFileBinary, then reads it back with
/// pcl::io::loadPCDFile. Throws core::Error("bench peers: pcl: ...") on PCL failures.
PclIo pclWriteRead(const core::PointCloud& cloud, const std::filesystem::path& path);

/// Reads a PCD file (ours) with pcl::io::loadPCDFile and returns its point count and
/// whether every field equals `expected`'s (the interoperability check).
bool pclReadsOurs(const std::filesystem::path& path, const core::PointCloud& expected, std::size_t* points);

/// pcl::ProgressiveMorphologicalFilter parameters (PCL's ground-filtering tutorial values
/// except the window, sized to the largest building of the bundled scenes).
struct PmfOptions {
    int max_window_size = 16;  // windows 3, 5, 9, 17 m (cell 1 m, base 2, exponential)
    float slope = 1.0f;
    float initial_distance_m = 0.5f;
    float max_distance_m = 3.0f;
    float cell_size_m = 1.0f;
};
/// Runs the filter on `points` (one thread, PCL's implementation) and returns a flag per
/// point, 1 = ground; `seconds` gets the filter's wall time.
std::vector<std::uint8_t> pclGroundPmf(std::span<const glm::vec3> points, const PmfOptions& options, double* seconds);

}  // namespace bench::peers
