// Tests for io/point_packing.hpp: a point packed for the COPC writer's scratch
// files comes back with every field the cloud carries, in as many bytes as those fields.
#include <io/point_packing.hpp>

#include <doctest/doctest.h>

#include <array>
#include <cstring>

namespace {

core::CloudPoint sample() {
    core::CloudPoint p;
    p.position = {1.5f, -2.25f, 1000.125f};
    p.rgb = 0x123456u;
    p.range_m = 301.5f;
    p.incidence_deg = 33.0f;
    p.scan_angle_deg = -12.5f;
    p.height_above_ground_m = 2.75f;
    p.intensity = 54321;
    p.view = 977;
    p.label = core::Role::Target;
    p.return_number = 2;
    p.returns = 3;
    return p;
}

}  // namespace

TEST_CASE("packed_point: every field of a cloud that has them all survives, in 39 bytes") {
    core::CloudFields all;
    all.intensity = all.returns = all.incidence = all.scan_angle = all.height_above_ground = true;
    const io::PointPacking packing(all);
    CHECK(packing.size() == 39);
    const core::CloudPoint p = sample();
    std::array<unsigned char, 64> bytes{};
    bytes.fill(0xAB);
    packing.pack(p, bytes.data());
    CHECK(bytes[packing.size()] == 0xAB);  // nothing written past the record
    const core::CloudPoint q = packing.unpack(bytes.data());
    CHECK(std::memcmp(&p, &q, sizeof p) == 0);
}

TEST_CASE("packed_point: a cloud of x y z alone keeps what a LAS record needs, in 17 bytes") {
    core::CloudFields xyz;
    xyz.rgb = xyz.label = xyz.view = xyz.range = false;
    const io::PointPacking packing(xyz);
    CHECK(packing.size() == 17);
    const core::CloudPoint p = sample();
    std::array<unsigned char, 64> bytes{};  // more than any packing takes
    packing.pack(p, bytes.data());
    const core::CloudPoint q = packing.unpack(bytes.data());
    CHECK(q.position == p.position);
    CHECK(q.view == p.view);
    CHECK(q.label == p.label);
    CHECK(q.return_number == p.return_number);
    CHECK(q.returns == p.returns);
    const core::CloudPoint defaults;
    CHECK(q.rgb == defaults.rgb);
    CHECK(q.range_m == defaults.range_m);
    CHECK(q.intensity == defaults.intensity);
    CHECK(q.scan_angle_deg == defaults.scan_angle_deg);
}

TEST_CASE("packed_point: a quantized packing holds the integer coordinates in the position's place") {
    core::CloudFields all;
    all.intensity = all.returns = all.incidence = all.scan_angle = all.height_above_ground = true;
    const io::PointPacking packing(all, io::PointPacking::Position::Quantized);
    CHECK(packing.size() == 39);
    const core::CloudPoint p = sample();
    const std::array<std::int32_t, 3> xyz{-2147483647, 0, 2147483647};
    std::array<unsigned char, 64> bytes{};
    bytes.fill(0xAB);
    packing.packQuantized(p, xyz, bytes.data());
    CHECK(bytes[packing.size()] == 0xAB);
    CHECK(io::PointPacking::quantized(bytes.data()) == xyz);
    const core::CloudPoint q = packing.unpack(bytes.data());
    CHECK(q.position == core::CloudPoint{}.position);  // the integers are not a position
    core::CloudPoint without = p;
    without.position = q.position;
    CHECK(std::memcmp(&without, &q, sizeof q) == 0);
}
