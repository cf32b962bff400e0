// bench/src/peers_pcl.cpp: PCL's PCD writer/reader and progressive morphological
// filter for `ladarvr bench peers` (the only file that includes PCL).
#include "peers_pcl.hpp"

#include "common.hpp"

#include <core/error.hpp>

#define PCL_NO_PRECOMPILE
#include <pcl/io/pcd_io.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/register_point_struct.h>
#include <pcl/segmentation/progressive_morphological_filter.h>

#include <chrono>
#include <cstring>

namespace bench::peers {

/// Our PCD fields as a PCL point type, so both writers produce the same columns.
struct EIGEN_ALIGN16 LadarPoint {
    PCL_ADD_POINT4D;
    float rgb;
    std::uint8_t label;
    std::uint16_t view;
    float range;
    PCL_MAKE_ALIGNED_OPERATOR_NEW
};

}  // namespace bench::peers

POINT_CLOUD_REGISTER_POINT_STRUCT(bench::peers::LadarPoint,
                                  (float, x, x)(float, y, y)(float, z, z)(float, rgb, rgb)(std::uint8_t, label, label)(
                                      std::uint16_t, view, view)(float, range, range))

namespace bench::peers {
namespace {

bool samePoints(const pcl::PointCloud<LadarPoint>& a, const core::PointCloud& b) {
    if (a.size() != b.points.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i) {
        const LadarPoint& p = a[i];
        const core::CloudPoint& q = b.points[i];
        std::uint32_t rgb = 0;
        std::memcpy(&rgb, &p.rgb, 4);
        if (p.x != q.position.x || p.y != q.position.y || p.z != q.position.z || rgb != q.rgb ||
            p.label != std::uint8_t(q.label) || p.view != q.view || p.range != q.range_m)
            return false;
    }
    return true;
}

}  // namespace

PclIo pclWriteRead(const core::PointCloud& cloud, const std::filesystem::path& path) {
    pcl::PointCloud<LadarPoint> pc;
    pc.resize(cloud.points.size());
    for (std::size_t i = 0; i < cloud.points.size(); ++i) {
        const core::CloudPoint& q = cloud.points[i];
        LadarPoint& p = pc[i];
        p.x = q.position.x;
        p.y = q.position.y;
        p.z = q.position.z;
        std::memcpy(&p.rgb, &q.rgb, 4);
        p.label = std::uint8_t(q.label);
        p.view = q.view;
        p.range = q.range_m;
    }
    PclIo r;
    std::error_code ec;
    std::filesystem::remove(path, ec);
    auto t0 = Clock::now();
    if (pcl::io::savePCDFileBinary(path.string(), pc) != 0)
        throw core::Error("bench peers: pcl: savePCDFileBinary failed on " + path.string());
    r.write_s = secondsSince(t0);
    pcl::PointCloud<LadarPoint> back;
    t0 = Clock::now();
    if (pcl::io::loadPCDFile(path.string(), back) != 0)
        throw core::Error("bench peers: pcl: loadPCDFile failed on " + path.string());
    r.read_s = secondsSince(t0);
    r.points_read = back.size();
    r.same_points = samePoints(back, cloud);
    return r;
}

bool pclReadsOurs(const std::filesystem::path& path, const core::PointCloud& expected, std::size_t* points) {
    pcl::PointCloud<LadarPoint> back;
    if (pcl::io::loadPCDFile(path.string(), back) != 0) return false;
    if (points) *points = back.size();
    return samePoints(back, expected);
}

std::vector<std::uint8_t> pclGroundPmf(std::span<const glm::vec3> points, const PmfOptions& options, double* seconds) {
    pcl::PointCloud<pcl::PointXYZ>::Ptr pc(new pcl::PointCloud<pcl::PointXYZ>);
    pc->resize(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) (*pc)[i] = pcl::PointXYZ(points[i].x, points[i].y, points[i].z);
    pcl::ProgressiveMorphologicalFilter<pcl::PointXYZ> pmf;
    pmf.setInputCloud(pc);
    pmf.setMaxWindowSize(options.max_window_size);
    pmf.setSlope(options.slope);
    pmf.setInitialDistance(options.initial_distance_m);
    pmf.setMaxDistance(options.max_distance_m);
    pmf.setCellSize(options.cell_size_m);
    pcl::Indices ground;
    const auto t0 = Clock::now();
    pmf.extract(ground);
    if (seconds) *seconds = secondsSince(t0);
    std::vector<std::uint8_t> flags(points.size(), 0);
    for (const auto i : ground) flags[std::size_t(i)] = 1;
    return flags;
}

}  // namespace bench::peers
