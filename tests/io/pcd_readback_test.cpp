// tests/io/pcd_readback_test.cpp: PCL reads the PCD files io writes (binary and
// ASCII) with every point's position, colour and label intact. The only test file that
// includes PCL.
#include <test_files.hpp>

#include <core/point_cloud.hpp>
#include <io/cloud_io.hpp>

#include <pcl/io/pcd_io.h>
#include <pcl/point_types.h>

#include <doctest/doctest.h>

#include <cstdint>

namespace {

/// 2,000 points with distinct positions (fractions of a metre, negative and far from the
/// local origin), colours in every channel and all three labels, far from the world origin.
core::PointCloud knownCloud() {
    core::PointCloud cloud;
    cloud.origin = glm::dvec3(651000.0, 6862000.0, 85.0);
    for (int i = 0; i < 2000; ++i) {
        core::CloudPoint p;
        p.position = glm::vec3(-400.0f + 0.37f * float(i), 12.5f - 0.011f * float(i), float(i % 50) * 0.25f - 3.0f);
        p.rgb = core::packRgb(std::uint8_t(i % 256), std::uint8_t((7 * i) % 256), std::uint8_t(255 - i % 256));
        p.label = core::Role(i % core::kRoleCount);
        p.view = std::uint16_t(i % 64);
        p.range_m = 100.0f + float(i);
        cloud.points.push_back(p);
    }
    return cloud;
}

}  // namespace

TEST_CASE("pcl::io::loadPCDFile reads our binary and ASCII PCD with every point intact") {
    const test_support::TempDir dir("pcd_readback");
    const core::PointCloud ours = knownCloud();
    for (const auto format : {io::CloudFormat::PcdBinary, io::CloudFormat::PcdAscii}) {
        const bool binary = format == io::CloudFormat::PcdBinary;
        CAPTURE(binary);
        const std::filesystem::path file = dir.path / (binary ? "binary.pcd" : "ascii.pcd");
        io::writeCloud(file, ours, format);
        pcl::PointCloud<pcl::PointXYZRGBL> theirs;
        REQUIRE(pcl::io::loadPCDFile(file.string(), theirs) == 0);
        REQUIRE(theirs.size() == ours.points.size());
        std::size_t wrong = 0;
        for (std::size_t i = 0; i < theirs.size(); ++i) {
            const core::CloudPoint& o = ours.points[i];
            const pcl::PointXYZRGBL& t = theirs[i];
            // Binary stores the float bits; ASCII enough digits to give back the same float.
            const bool position = t.x == o.position.x && t.y == o.position.y && t.z == o.position.z;
            const bool colour = core::packRgb(t.r, t.g, t.b) == o.rgb;
            const bool label = t.label == std::uint32_t(o.label);
            wrong += !(position && colour && label);
        }
        CHECK(wrong == 0);
    }
}

TEST_CASE("PCL's count of our PCD and our LAS reader's count of the same cloud's LAS/LAZ agree") {
    const test_support::TempDir dir("pcl_las_counts");
    const core::PointCloud ours = knownCloud();
    io::writeCloud(dir.path / "c.pcd", ours, io::CloudFormat::PcdBinary);
    pcl::PointCloud<pcl::PointXYZRGBL> theirs;
    REQUIRE(pcl::io::loadPCDFile((dir.path / "c.pcd").string(), theirs) == 0);
    for (const auto format : {io::CloudFormat::Las, io::CloudFormat::Laz}) {
        const std::filesystem::path file = dir.path / (format == io::CloudFormat::Las ? "c.las" : "c.laz");
        io::writeCloud(file, ours, format);
        const core::PointCloud las = io::readCloud(file);
        REQUIRE(las.points.size() == theirs.size());
        std::size_t wrong = 0;
        for (std::size_t i = 0; i < theirs.size(); ++i) {
            const glm::dvec3 w = las.origin + glm::dvec3(las.points[i].position);
            const glm::dvec3 p = ours.origin + glm::dvec3(theirs[i].x, theirs[i].y, theirs[i].z);
            wrong += glm::length(w - p) > 0.001 || std::uint32_t(las.points[i].label) != theirs[i].label;
        }
        CHECK(wrong == 0);
    }
}
