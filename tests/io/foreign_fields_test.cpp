// tests/io/foreign_fields_test.cpp: a real survey's side records (core::ForeignPoint and
// its extra bytes) read by CloudReader with SideRecords::Keep and written back by the
// LAS, LAZ and COPC writers, read again: every record the same, the CRS kept or made
// from GeoTIFF keys, and none kept for a cloud we generated.
#include <test_files.hpp>

#include <core/point_cloud.hpp>
#include <io/cloud_io.hpp>
#include <io/cloud_reader.hpp>
#include <io/copc_writer.hpp>

#include <doctest/doctest.h>

#include <algorithm>
#include <cstring>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

using test_support::TempDir;

const fs::path kReal = fs::path(LADARVR_TEST_DATA_DIR) / "real";

core::PointCloud readKept(const fs::path& file) {
    io::CloudReader reader(file, io::SideRecords::Keep);
    core::PointCloud cloud;
    cloud.origin = reader.origin();
    cloud.fields = reader.fields();
    const auto header = reader.foreignHeader();
    if (header) {
        cloud.foreign.emplace();
        cloud.foreign->header = *header;
    }
    std::vector<unsigned char> none;
    while (reader.nextChunk(cloud.points, header ? cloud.foreign->records : none)) {}
    return cloud;
}

// Each point's record with its integer position (mm from the origin) in front, sorted:
// the points of a COPC file come in the octree's order.
std::vector<std::string> keyed(const core::PointCloud& c) {
    const std::size_t stride = c.foreign->header.stride();
    std::vector<std::string> out;
    for (std::size_t i = 0; i < c.points.size(); ++i) {
        const glm::dvec3 world = c.origin + glm::dvec3(c.points[i].position);
        std::string k = std::to_string(std::llround(world.x * 100)) + "," +
                        std::to_string(std::llround(world.y * 100)) + "," +
                        std::to_string(std::llround(world.z * 100)) + ":";
        k.append(reinterpret_cast<const char*>(c.foreign->records.data() + i * stride), stride);
        out.push_back(std::move(k));
    }
    std::sort(out.begin(), out.end());
    return out;
}

}  // namespace

TEST_CASE("foreign fields: a real survey's side records survive LAS, LAZ and COPC") {
    TempDir dir("foreign_fields");
    for (const char* name : {"sample_c.las", "mvk-thin.las", "4_6_crop.las"}) {
        CAPTURE(name);
        const core::PointCloud in = readKept(kReal / name);
        REQUIRE(in.foreign);
        REQUIRE(in.foreign->records.size() == in.points.size() * in.foreign->header.stride());
        // mvk-thin and 4_6_crop have GeoTIFF keys only: PROJ makes their WKT.
        CHECK(in.foreign->header.wkt.empty() == (std::string(name) == "sample_c.las"));
        for (const char* out_name : {"o.las", "o.laz", "o.copc.laz"}) {
            CAPTURE(out_name);
            const fs::path out = dir.path / out_name;
            io::writeCloud(out, in, io::formatForPath(out));
            const core::PointCloud back = readKept(out);
            REQUIRE(back.foreign);
            CHECK(back.foreign->header.wkt.rfind(in.foreign->header.wkt, 0) == 0);
            CHECK(back.foreign->header.extra_bytes == in.foreign->header.extra_bytes);
            REQUIRE(back.points.size() == in.points.size());
            CHECK(keyed(back) == keyed(in));
        }
        // writeCopc, the whole-cloud COPC writer, too.
        const fs::path whole = dir.path / "w.copc.laz";
        io::writeCopc(whole, in);
        const core::PointCloud back = readKept(whole);
        REQUIRE(back.foreign);
        CHECK(keyed(back) == keyed(in));
    }
}

TEST_CASE("foreign fields: classes above 31 and the flags round-trip, and a generated cloud keeps none") {
    TempDir dir("foreign_fields_classes");
    core::PointCloud in = readKept(kReal / "sample_c.las");
    REQUIRE(in.foreign);
    const std::size_t stride = in.foreign->header.stride();
    for (std::size_t i = 0; i < in.points.size(); ++i) {
        core::ForeignPoint f;
        std::memcpy(&f, in.foreign->records.data() + i * stride, sizeof f);
        f.classification = std::uint8_t(i % 256);
        f.flags = std::uint8_t(i % 256);
        f.user_data = std::uint8_t(i * 7);
        f.nir = std::uint16_t(i * 3);  // not kept: sample_c has no near infrared
        std::memcpy(in.foreign->records.data() + i * stride, &f, sizeof f);
    }
    const fs::path out = dir.path / "c.las";
    io::writeCloud(out, in, io::CloudFormat::Las);
    const core::PointCloud back = readKept(out);
    REQUIRE(back.foreign);
    REQUIRE(back.points.size() == in.points.size());
    for (std::size_t i = 0; i < in.points.size(); i += 97) {
        core::ForeignPoint a, b;
        std::memcpy(&a, in.foreign->records.data() + i * stride, sizeof a);
        std::memcpy(&b, back.foreign->records.data() + i * stride, sizeof b);
        CHECK(int(b.classification) == int(a.classification));
        CHECK(int(b.flags) == int(a.flags));
        CHECK(int(b.user_data) == int(a.user_data));
        CHECK(b.gps_time_s == a.gps_time_s);
        CHECK(b.rgb[0] == a.rgb[0]);
        CHECK(b.point_source_id == a.point_source_id);
    }

    // A cloud we generated (our `label` extra bytes) is read without side records.
    core::PointCloud ours;
    ours.points.resize(10);
    const fs::path generated = dir.path / "g.las";
    io::writeCloud(generated, ours, io::CloudFormat::Las);
    io::CloudReader reader(generated, io::SideRecords::Keep);
    CHECK(!reader.foreignHeader());
}
