// tests/viewer/pcd_stream_test.cpp: the viewer's streaming PCD reader and its CloudFeed.
#include "pcd_stream.hpp"

#include <engine/cloud_io.hpp>
#include <engine/error.hpp>
#include <viewer/cloud_feed.hpp>

#include <doctest/doctest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <thread>
#include <unistd.h>

using namespace viewer;

namespace {
std::filesystem::path tempPath(const std::string& name) {
    return std::filesystem::temp_directory_path() /
           ("ladarvr-viewer-" + std::to_string(::getpid()) + "-" + name);
}

engine::PointCloud sampleCloud(std::size_t n) {
    engine::PointCloud cloud;
    cloud.origin = glm::dvec3(1.0e6, 2.0e6, 30.0);   // georeferenced far away
    for (std::size_t i = 0; i < n; ++i) {
        engine::CloudPoint p;
        p.position = glm::vec3(float(i) * 0.25f, -float(i % 17), float(i % 5) * 0.5f);
        p.rgb = engine::packRgb(std::uint8_t(i), std::uint8_t(255 - i % 256), 7);
        p.range_m = 300.0f + float(i);
        p.view = std::uint16_t(i % 100);
        p.label = static_cast<engine::Role>(i % 3);
        cloud.points.push_back(p);
    }
    return cloud;
}

std::vector<engine::CloudPoint> drain(CloudFeed& feed, std::vector<std::size_t>* sizes = nullptr) {
    std::vector<engine::CloudPoint> all;
    for (auto& chunk : feed.take()) {
        CHECK(chunk.cells.empty());   // no LOD order unless enabled: file order kept
        if (sizes) sizes->push_back(chunk.points.size());
        all.insert(all.end(), chunk.points.begin(), chunk.points.end());
    }
    return all;
}

void checkSame(const std::vector<engine::CloudPoint>& got, const engine::PointCloud& want) {
    REQUIRE(got.size() == want.points.size());
    for (std::size_t i = 0; i < got.size(); ++i) {
        CHECK(got[i].position == want.points[i].position);
        CHECK(got[i].rgb == want.points[i].rgb);
        CHECK(got[i].label == want.points[i].label);
        CHECK(got[i].view == want.points[i].view);
        CHECK(got[i].range_m == want.points[i].range_m);
    }
}
}  // namespace

TEST_CASE("a binary PCD streams in chunks with its origin and every field") {
    const auto cloud = sampleCloud(1000);
    const auto path = tempPath("stream.pcd");
    engine::writeCloud(path, cloud, engine::CloudFormat::PcdBinary);
    CloudFeed feed;
    REQUIRE(streamBinaryPcd(path, feed, 300));
    std::vector<std::size_t> sizes;
    const auto got = drain(feed, &sizes);
    CHECK(sizes == std::vector<std::size_t>{300, 300, 300, 100});
    CHECK(feed.origin() == cloud.origin);
    CHECK(feed.pointsArrived() == 1000);
    checkSame(got, cloud);
    std::filesystem::remove(path);
}

TEST_CASE("other formats go through engine::readCloud on the loader thread") {
    const auto cloud = sampleCloud(500);
    for (auto format : {engine::CloudFormat::PcdAscii, engine::CloudFormat::PlyBinary}) {
        const auto path = tempPath(format == engine::CloudFormat::PcdAscii ? "a.pcd" : "b.ply");
        engine::writeCloud(path, cloud, format);
        CloudFeed probe;
        CHECK_FALSE(streamBinaryPcd(path, probe, 100));
        CHECK(probe.pointsArrived() == 0);

        CloudFeed feed;
        feed.startFileLoader(path, 128);
        for (int i = 0; i < 500 && !feed.finished(); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
        REQUIRE(feed.finished());
        CHECK(feed.error().empty());
        CHECK(feed.origin() == cloud.origin);
        const auto got = drain(feed);
        REQUIRE(got.size() == 500);
        CHECK(got[499].position == cloud.points[499].position);
        CHECK(got[123].label == cloud.points[123].label);
        std::filesystem::remove(path);
    }
}

TEST_CASE("a truncated binary PCD keeps the points read and reports the truncation") {
    const auto cloud = sampleCloud(1000);
    const auto path = tempPath("cut.pcd");
    engine::writeCloud(path, cloud, engine::CloudFormat::PcdBinary);
    // Bytes per point from the file itself: the data follows the "DATA binary" line.
    std::string text(std::filesystem::file_size(path), '\0');
    std::ifstream(path, std::ios::binary).read(text.data(), std::streamsize(text.size()));
    const std::size_t data_at = text.find("DATA binary\n") + 12;
    const std::size_t stride = (text.size() - data_at) / 1000;
    REQUIRE(stride * 1000 == text.size() - data_at);
    std::filesystem::resize_file(path, text.size() - 5000);
    const std::size_t whole_points = (1000 * stride - 5000) / stride;
    CloudFeed feed;
    feed.startFileLoader(path, 256);
    for (int i = 0; i < 500 && !feed.finished(); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    REQUIRE(feed.finished());
    CHECK(feed.error().find("truncated") != std::string::npos);
    CHECK(feed.error().find("cut.pcd") != std::string::npos);
    CHECK(drain(feed).size() == whole_points / 256 * 256);   // the whole chunks before the cut
    std::filesystem::remove(path);
}

TEST_CASE("a missing file ends the feed with the reader's error") {
    CloudFeed feed;
    feed.startFileLoader(tempPath("missing.pcd"));
    for (int i = 0; i < 500 && !feed.finished(); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    REQUIRE(feed.finished());
    CHECK_FALSE(feed.error().empty());
    CHECK(feed.pointsArrived() == 0);
}
