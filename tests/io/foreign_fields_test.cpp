// tests/io/foreign_fields_test.cpp: a real survey's side records (core::ForeignPoint and
// its extra bytes) read by CloudReader with SideRecords::Keep and written back by the
// LAS, LAZ and COPC writers, read again: every record the same, the CRS kept or made
// from GeoTIFF keys, the input's scale and offset and its extra bytes descriptors kept,
// and none kept for a cloud we generated.
#include <test_files.hpp>
#include <test_paths.hpp>

#include <core/point_cloud.hpp>
#include <io/cloud_info.hpp>
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

const fs::path kReal = fs::path(test_support::dataDir()) / "real";

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

// Each point's record (without its integer coordinates unless `with_xyz`) with its
// integer position (mm from the origin) in front, sorted:
// the points of a COPC file come in the octree's order.
std::vector<std::string> keyed(const core::PointCloud& c, bool with_xyz = true) {
    const std::size_t stride = c.foreign->header.stride();
    std::vector<std::string> out;
    for (std::size_t i = 0; i < c.points.size(); ++i) {
        const glm::dvec3 world = c.origin + glm::dvec3(c.points[i].position);
        std::string k = std::to_string(std::llround(world.x * 100)) + "," +
                        std::to_string(std::llround(world.y * 100)) + "," +
                        std::to_string(std::llround(world.z * 100)) + ":";
        k.append(reinterpret_cast<const char*>(c.foreign->records.data() + i * stride), stride);
        if (!with_xyz) std::fill_n(k.end() - std::ptrdiff_t(stride) + 8, 12, '\0');  // ForeignPoint::xyz
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

namespace {

// A 192-byte extra bytes descriptor with every optional field set: no-data, minimum,
// maximum, scale and offset (LAS 1.4 R15 §2.6.3), of an int16 field.
std::string fullDescriptor(const char* name) {
    std::string d(192, '\0');
    d[2] = 4;                         // int16
    d[3] = char(1 | 2 | 4 | 8 | 16);  // no_data, min, max, scale, offset
    std::memcpy(d.data() + 4, name, std::strlen(name));
    const std::int64_t no_data = -32768, lo = -300, hi = 300;
    const double scale = 0.1, offset = 2.5;
    std::memcpy(d.data() + 40, &no_data, 8);
    std::memcpy(d.data() + 64, &lo, 8);
    std::memcpy(d.data() + 88, &hi, 8);
    std::memcpy(d.data() + 112, &scale, 8);
    std::memcpy(d.data() + 136, &offset, 8);
    std::memcpy(d.data() + 160, "deviation in tenths", 19);
    return d;
}

// `in` with `extra` bytes after each side record (byte k of point i: i + k) described by
// `vlr`.
core::PointCloud withExtraBytes(const core::PointCloud& in, std::size_t extra, const std::string& vlr) {
    core::PointCloud out = in;
    const std::size_t from = in.foreign->header.stride();
    out.foreign->header.extra_bytes = extra;
    out.foreign->header.extra_bytes_vlr = vlr;
    const std::size_t to = out.foreign->header.stride();
    out.foreign->records.assign(in.points.size() * to, 0);
    for (std::size_t i = 0; i < in.points.size(); ++i) {
        std::memcpy(out.foreign->records.data() + i * to, in.foreign->records.data() + i * from,
                    sizeof(core::ForeignPoint));
        for (std::size_t k = 0; k < extra; ++k)
            out.foreign->records[i * to + sizeof(core::ForeignPoint) + k] = std::uint8_t(i + k);
    }
    return out;
}

}  // namespace

TEST_CASE("foreign fields: the input's scale and offset are the output's, one scale in COPC") {
    TempDir dir("foreign_fields_scale");
    core::PointCloud in = readKept(kReal / "sample_c.las");
    REQUIRE(in.foreign);
    CHECK(in.foreign->header.scale == glm::dvec3(0.01));
    // A finer grid than the writers' 1 mm, finest on z, and an offset off the origin.
    in.foreign->header.scale = {0.00025, 0.00025, 0.0001};
    in.foreign->header.offset = in.origin + glm::dvec3(-12.34, 56.78, -9.1);
    for (const char* out_name : {"s.las", "s.laz", "s.copc.laz"}) {
        CAPTURE(out_name);
        const fs::path out = dir.path / out_name;
        io::writeCloud(out, in, io::formatForPath(out));
        const io::CloudInfo info = io::inspectCloud(out, "test");
        REQUIRE(info.las);
        const bool copc = std::string(out_name) == "s.copc.laz";
        // COPC: one scale that divides both, 0.05 mm.
        CHECK(info.las->scale == (copc ? glm::dvec3(0.0001 / 2) : in.foreign->header.scale));
        CHECK(info.las->offset == in.foreign->header.offset);
        const core::PointCloud back = readKept(out);
        REQUIRE(back.foreign);
        CHECK(back.foreign->header.scale == info.las->scale);
        REQUIRE(back.points.size() == in.points.size());
        // The records' integer coordinates are on the new grid.
        CHECK(keyed(back, false) == keyed(in, false));
    }
    // A cloud we generated keeps 1 mm and its origin.
    core::PointCloud ours;
    ours.origin = {1000.5, 2000.25, 30.0};
    ours.points.resize(3);
    io::writeCloud(dir.path / "g.las", ours, io::CloudFormat::Las);
    const io::CloudInfo info = io::inspectCloud(dir.path / "g.las", "test");
    REQUIRE(info.las);
    CHECK(info.las->scale == glm::dvec3(0.001));
    CHECK(info.las->offset == ours.origin);
}

TEST_CASE("foreign fields: extra bytes descriptors are written as the file has them") {
    TempDir dir("foreign_fields_descriptors");
    const core::PointCloud base = readKept(kReal / "sample_c.las");
    REQUIRE(base.foreign);
    const std::string full = fullDescriptor("Deviation");
    for (const char* out_name : {"d.las", "d.laz", "d.copc.laz"}) {
        CAPTURE(out_name);
        const fs::path out = dir.path / out_name;
        // Described bytes alone: the VLR comes back byte for byte, and so do the bytes.
        const core::PointCloud in = withExtraBytes(base, 2, full);
        io::writeCloud(out, in, io::formatForPath(out));
        const core::PointCloud back = readKept(out);
        REQUIRE(back.foreign);
        CHECK(back.foreign->header.extra_bytes_vlr == full);
        CHECK(keyed(back) == keyed(in));

        // With the height above ground added after a byte no descriptor covers: that byte
        // described as undocumented (type 0, one byte), then PDAL's HeightAboveGround.
        core::PointCloud hag = withExtraBytes(base, 3, full);
        hag.fields.height_above_ground = true;
        io::writeCloud(out, hag, io::formatForPath(out));
        const std::string v = readKept(out).foreign->header.extra_bytes_vlr;
        REQUIRE(v.size() == 3 * 192);
        CHECK(v.substr(0, 192) == full);
        CHECK(int(v[192 + 2]) == 0);
        CHECK(int(v[192 + 3]) == 1);
        CHECK(int(v[384 + 2]) == 9);
        CHECK(std::string(v.data() + 384 + 4) == "HeightAboveGround");
    }
}
