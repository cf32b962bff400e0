// tests/viewer/points/cloud_feed_test.cpp: the viewer's file loader (CloudFeed::feedFile on
// io::CloudReader): chunks with every field, the same refusals with the same line
// as io::readCloud for every bad file of the shared table, non-finite points
// dropped, and an empty or broken file ending the feed with an error and no points.
#include <bad_clouds.hpp>
#include <test_files.hpp>

#include <core/error.hpp>
#include <io/cloud_io.hpp>
#include <viewer/cloud_feed.hpp>

#include <doctest/doctest.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <thread>

using namespace viewer;
namespace fs = std::filesystem;
using test_support::TempDir;

namespace {

void spit(const fs::path& p, const std::string& bytes) { std::ofstream(p, std::ios::binary) << bytes; }

core::PointCloud sampleCloud(std::size_t n) {
    core::PointCloud cloud;
    cloud.origin = glm::dvec3(1.0e6, 2.0e6, 30.0);  // georeferenced far away
    for (std::size_t i = 0; i < n; ++i) {
        core::CloudPoint p;
        p.position = glm::vec3(float(i) * 0.25f, -float(i % 17), float(i % 5) * 0.5f);
        p.rgb = core::packRgb(std::uint8_t(i), std::uint8_t(255 - i % 256), 7);
        p.range_m = 300.0f + float(i);
        p.view = std::uint16_t(i % 100);
        p.label = static_cast<core::Role>(i % 3);
        cloud.points.push_back(p);
    }
    return cloud;
}

std::vector<core::CloudPoint> drain(CloudFeed& feed, std::vector<std::size_t>* sizes = nullptr) {
    std::vector<core::CloudPoint> all;
    for (auto& chunk : feed.take()) {
        CHECK(chunk.cells.empty());  // no LOD order unless enabled: file order kept
        if (sizes) sizes->push_back(chunk.points.size());
        all.insert(all.end(), chunk.points.begin(), chunk.points.end());
    }
    return all;
}

void checkSame(const std::vector<core::CloudPoint>& got, const std::vector<core::CloudPoint>& want) {
    REQUIRE(got.size() == want.size());
    for (std::size_t i = 0; i < got.size(); ++i) {
        CHECK(got[i].position == want[i].position);
        CHECK(got[i].rgb == want[i].rgb);
        CHECK(got[i].label == want[i].label);
        CHECK(got[i].view == want[i].view);
        CHECK(got[i].range_m == want[i].range_m);
    }
}

std::string engineError(const fs::path& p) {
    try {
        io::readCloud(p);
    } catch (const core::Error& e) {
        return e.what();
    }
    return "accepted";
}

}  // namespace

TEST_CASE("every format streams in chunks with its origin and every field") {
    TempDir dir("viewer_stream");
    const auto cloud = sampleCloud(1000);
    for (auto format : {io::CloudFormat::PcdBinary, io::CloudFormat::PcdAscii, io::CloudFormat::PlyBinary,
                        io::CloudFormat::PlyAscii}) {
        const bool ply = format == io::CloudFormat::PlyBinary || format == io::CloudFormat::PlyAscii;
        const auto path = dir.path / ("s" + std::to_string(int(format)) + (ply ? ".ply" : ".pcd"));
        io::writeCloud(path, cloud, format);
        CAPTURE(path.string());
        CloudFeed feed;
        feed.feedFile(path, 300);
        REQUIRE(feed.finished());
        CHECK(feed.error().empty());
        std::vector<std::size_t> sizes;
        const auto got = drain(feed, &sizes);
        CHECK(sizes == std::vector<std::size_t>{300, 300, 300, 100});
        CHECK(feed.origin() == cloud.origin);
        CHECK(feed.pointsArrived() == 1000);
        checkSame(got, cloud.points);
    }
}

TEST_CASE("the loader thread feeds the same points") {
    TempDir dir("viewer_thread");
    const auto cloud = sampleCloud(500);
    const auto path = dir.path / "t.pcd";
    io::writeCloud(path, cloud, io::CloudFormat::PcdBinary);
    CloudFeed feed;
    feed.startFileLoader(path, 128);
    feed.waitFinished();
    REQUIRE(feed.finished());
    CHECK(feed.error().empty());
    checkSame(drain(feed), cloud.points);
}

TEST_CASE("the viewer refuses exactly the files io refuses, with the same line") {
    TempDir dir("viewer_bad");
    for (const test_support::BadCloud& bad : test_support::badClouds()) {
        CAPTURE(bad.name);
        const fs::path p = dir.path / bad.name;
        spit(p, bad.bytes);
        const std::string engine_says = engineError(p);
        CHECK(engine_says.find(bad.message) != std::string::npos);
        CloudFeed feed;
        feed.feedFile(p, 1);  // chunks of one point: nothing of a bad header gets through
        REQUIRE(feed.finished());
        CHECK(feed.error() == engine_says);
        if (!bad.in_records) CHECK(feed.pointsArrived() == 0);
    }
}

TEST_CASE("a truncated binary file is refused before any point is shown") {
    TempDir dir("viewer_cut");
    const auto cloud = sampleCloud(1000);
    const auto path = dir.path / "cut.pcd";
    io::writeCloud(path, cloud, io::CloudFormat::PcdBinary);
    fs::resize_file(path, fs::file_size(path) - 5000);
    CloudFeed feed;
    feed.feedFile(path, 256);
    CHECK(feed.error().find("pcd: " + path.string() + ": truncated: the header says 1000 points") == 0);
    CHECK(feed.pointsArrived() == 0);
    CHECK(drain(feed).empty());
}

TEST_CASE("NaN and inf points are dropped, and a file with no point left is an error") {
    TempDir dir("viewer_nonfinite");
    auto cloud = sampleCloud(600);
    cloud.points[10].position.y = std::numeric_limits<float>::infinity();
    cloud.points[400].position.x = std::nanf("");
    const auto path = dir.path / "inf.pcd";
    io::writeCloud(path, cloud, io::CloudFormat::PcdBinary);
    CloudFeed feed;
    feed.feedFile(path, 256);
    CHECK(feed.error().empty());
    CHECK(feed.pointsArrived() == 598);
    const auto got = drain(feed);
    REQUIRE(got.size() == 598);
    CHECK(got[10].position == cloud.points[11].position);
    for (const auto& p : got) CHECK(std::isfinite(p.position.x + p.position.y + p.position.z));

    core::PointCloud none;
    none.points.resize(3);
    for (auto& p : none.points) p.position.z = std::numeric_limits<float>::infinity();
    const auto all_bad = dir.path / "allbad.pcd";
    io::writeCloud(all_bad, none, io::CloudFormat::PcdBinary);
    CloudFeed bad;
    bad.feedFile(all_bad, 256);
    CHECK(bad.error() == "pcd: " + all_bad.string() + ": holds no points to show");
    CHECK(bad.pointsArrived() == 0);
}

TEST_CASE("a file of 0 points ends the feed with an error") {
    TempDir dir("viewer_empty");
    const auto path = dir.path / "empty.ply";
    io::writeCloud(path, core::PointCloud{}, io::CloudFormat::PlyBinary);
    CloudFeed feed;
    feed.feedFile(path, 256);
    REQUIRE(feed.finished());
    CHECK(feed.error() == "ply: " + path.string() + ": holds no points to show");
}

TEST_CASE("a missing file ends the feed with the reader's error") {
    TempDir dir("viewer_missing");
    CloudFeed feed;
    feed.startFileLoader(dir.path / "missing.pcd");
    feed.waitFinished();
    REQUIRE(feed.finished());
    CHECK(feed.error() == "pcd: " + (dir.path / "missing.pcd").string() + ": file does not exist");
    CHECK(feed.pointsArrived() == 0);
}
