// tests/io/cloud_info_test.cpp: io::inspectCloud on PCD and PLY (io/src/cloud_info.cpp):
// the format, version and encoding the header states, the point count, the bounds of the
// finite points in world coordinates and the fields; the reader chosen by content, not by
// the file's name; bad files refused in one line.
#include <test_files.hpp>
#include <test_paths.hpp>
#include <core/error.hpp>
#include <io/cloud_info.hpp>
#include <io/cloud_io.hpp>

#include <doctest/doctest.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <string>

namespace fs = std::filesystem;

namespace {

using test_support::errorOf;
using test_support::slurp;
using test_support::TempDir;

const fs::path kData = fs::path(test_support::dataDir()) / "io";

using Fields = std::vector<std::string>;

}  // namespace

TEST_CASE("cloud_info: PCL's PCD files: version, encoding, count, bounds and fields") {
    // 300 points: x = i/4, y = -1.5 (i % 17), z = (i / 10) / 2 (tests/data/io/README.md).
    for (const char* encoding : {"ascii", "binary", "binary_compressed"}) {
        CAPTURE(encoding);
        const io::CloudInfo info = io::inspectCloud(kData / ("pcl_" + std::string(encoding) + ".pcd"), "info");
        CHECK(info.format == "PCD");
        CHECK(info.version == "0.7");
        CHECK(info.encoding == encoding);
        CHECK(info.points == 300);
        CHECK(info.non_finite == 0);
        REQUIRE(info.has_bounds);
        CHECK(info.min == glm::dvec3(0.0, -24.0, 0.0));
        CHECK(info.max == glm::dvec3(74.75, 0.0, 14.5));
        CHECK(info.fields == Fields{"x", "y", "z", "rgb", "label", "view", "range"});
        CHECK_FALSE(info.las);
    }
}

TEST_CASE("cloud_info: our PLY: world bounds through the origin, non-finite points counted apart") {
    TempDir dir("cloud_info_ply");
    core::PointCloud c;
    c.origin = {500000.0, 4000000.0, 10.0};
    c.fields.range = false;
    for (int i = 0; i < 10; ++i) {
        core::CloudPoint p;
        p.position = {float(i), -float(i), 0.5f * float(i)};
        c.points.push_back(p);
    }
    c.points[4].position.y = std::numeric_limits<float>::quiet_NaN();
    const fs::path path = dir.path / "c.ply";
    io::writeCloud(path, c, io::CloudFormat::PlyBinary);
    // Named .pcd: the content decides.
    fs::rename(path, dir.path / "c.pcd");
    const io::CloudInfo info = io::inspectCloud(dir.path / "c.pcd", "info");
    CHECK(info.format == "PLY");
    CHECK(info.version == "1.0");
    CHECK(info.encoding == "binary_little_endian");
    CHECK(info.points == 10);
    CHECK(info.non_finite == 1);
    CHECK(info.min == glm::dvec3(500000.0, 4000000.0 - 9.0, 10.0));
    CHECK(info.max == glm::dvec3(500009.0, 4000000.0, 14.5));
    CHECK(info.fields == Fields{"x", "y", "z", "rgb", "label", "view"});
    CHECK(info.file_bytes == fs::file_size(dir.path / "c.pcd"));
}

TEST_CASE("cloud_info: bad files: one line naming the file and what is wrong") {
    TempDir dir("cloud_info_bad");
    const fs::path empty_las = dir.write("empty.las", "");
    CHECK(errorOf([&] { io::inspectCloud(empty_las, "info"); }) ==
          "info: " + empty_las.string() + ": truncated: a LAS header needs 227 bytes, the file has 0");
    const fs::path text = dir.write("notes.txt", "hello\n");
    const std::string e = errorOf([&] { io::inspectCloud(text, "info"); });
    CHECK(e.rfind("info: " + text.string() + ": ", 0) == 0);
    CHECK(e.find('\n') == std::string::npos);
    CHECK(errorOf([&] { io::inspectCloud(dir.path, "info"); }) ==
          "info: " + dir.path.string() + ": is a directory, not a regular file");
}
