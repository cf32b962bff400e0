// tests/viewer/points/point_attributes_test.cpp: a point's class, stretched intensity and
// returns packed into the float its GPU record keeps for the height above ground: exact
// through the float, the class from the side record or else from the label, the stretch
// from the first chunk's 2nd and 98th percentiles and kept for the chunks after it.
#include "points/point_attributes.hpp"

#include <viewer/cloud_feed.hpp>

#include <doctest/doctest.h>

#include <cstring>
#include <vector>

using namespace viewer;

namespace {
std::uint32_t unpacked(const core::CloudPoint& p) { return std::uint32_t(p.height_above_ground_m); }
}  // namespace

TEST_CASE("point attributes: packed exactly into a float, classes from side records or labels") {
    CHECK(packAttributes(255, 255, 7, 7) == 0x3FFFFFu);
    CHECK(float(packAttributes(255, 255, 7, 7)) == 4194303.0f);           // below 2^24: exact
    CHECK(packAttributes(6, 0, 9, 9) == (6u | (7u << 16) | (7u << 19)));  // returns capped at 7
    CHECK(classOfLabel(core::Role::Ground) == 2);
    CHECK(classOfLabel(core::Role::Target) == 64);

    // 100 points, intensities 0..99 x 10: the 2nd percentile 10, the 98th 970.
    std::vector<core::CloudPoint> points(100);
    const std::size_t stride = sizeof(core::ForeignPoint) + 2;
    std::vector<unsigned char> records(points.size() * stride, 0);
    for (std::size_t i = 0; i < points.size(); ++i) {
        points[i].intensity = std::uint16_t(10 * i);
        points[i].return_number = 2;
        points[i].returns = 3;
        core::ForeignPoint f;
        f.classification = std::uint8_t(i % 20);
        std::memcpy(records.data() + i * stride, &f, sizeof f);
    }
    PointAttributes attributes;
    attributes.pack(points, records, stride);
    REQUIRE(attributes.stretch());
    CHECK(attributes.stretch()->lo == 10.0);
    CHECK(attributes.stretch()->hi == 970.0);
    CHECK((unpacked(points[7]) & 0xFFu) == 7u);
    CHECK(((unpacked(points[0]) >> 8) & 0xFFu) == 0u);     // below the 2nd percentile
    CHECK(((unpacked(points[99]) >> 8) & 0xFFu) == 255u);  // above the 98th
    CHECK(((unpacked(points[49]) >> 8) & 0xFFu) == 128u);  // (490 - 10) / 960 of 255, rounded
    CHECK(((unpacked(points[5]) >> 16) & 7u) == 2u);
    CHECK(((unpacked(points[5]) >> 19) & 7u) == 3u);

    // A later chunk keeps the first chunk's stretch; without side records the label decides.
    std::vector<core::CloudPoint> later(2);
    later[0].intensity = 10;
    later[0].label = core::Role::Ground;
    later[1].intensity = 5000;
    attributes.pack(later);
    CHECK(attributes.stretch()->hi == 970.0);
    CHECK(unpacked(later[0]) == packAttributes(2, 0, 1, 1));
    CHECK(unpacked(later[1]) == packAttributes(1, 255, 1, 1));
}

TEST_CASE(
    "point attributes: a fed cloud without heights above ground carries them, one with heights keeps its heights") {
    core::PointCloud cloud;
    cloud.points.resize(3);
    cloud.points[0].label = core::Role::Ground;
    cloud.points[2].height_above_ground_m = 4.5f;
    cloud.fields.height_above_ground = true;
    CloudFeed with_heights;
    with_heights.feedCloud(cloud);
    CHECK(with_heights.take().at(0).points[2].height_above_ground_m == 4.5f);

    cloud.fields.height_above_ground = false;
    CloudFeed without;
    without.feedCloud(cloud);
    const std::vector<FeedChunk> chunks = without.take();
    CHECK(unpacked(chunks.at(0).points[0]) == packAttributes(2, 0, 1, 1));
    CHECK(unpacked(chunks.at(0).points[2]) == packAttributes(1, 0, 1, 1));
}
