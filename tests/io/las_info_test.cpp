// tests/io/las_info_test.cpp: io::inspectCloud on LAS, LAZ and COPC (io/src/las/las_info.cpp):
// the real surveys of tests/data/real against the figures of their README (counts,
// classes, CRS and units), the colour depth of files our writer makes with their RGB set
// by hand, the extra bytes fields, a COPC file's nodes, and damaged files refused in one
// line naming the file and what is wrong.
#include "copc_test_file.hpp"

#include <test_files.hpp>
#include <test_paths.hpp>
#include <core/error.hpp>
#include <io/cloud_info.hpp>
#include <io/cloud_io.hpp>

#include <doctest/doctest.h>

#include <cstring>
#include <fstream>
#include <map>
#include <string>

namespace fs = std::filesystem;

namespace {

using test_support::errorOf;
using test_support::slurp;
using test_support::TempDir;

const fs::path kReal = fs::path(test_support::dataDir()) / "real";

template <typename T>
T get(const std::string& b, std::size_t at) {
    T v;
    std::memcpy(&v, b.data() + at, sizeof v);
    return v;
}

template <typename T>
void put(std::string& b, std::size_t at, T v) {
    std::memcpy(b.data() + at, &v, sizeof v);
}

fs::path spit(const fs::path& p, const std::string& bytes) {
    std::ofstream(p, std::ios::binary) << bytes;
    return p;
}

// A cloud of `n` points with colour (red i, green 2i, blue 3i, mod 256) and our extra
// bytes (range, label), as our LAS writer writes it: RGB are 16-bit (v * 257).
std::string written(const TempDir& dir, int n = 500) {
    core::PointCloud c;
    c.origin = {500000.0, 4000000.0, 100.0};
    c.fields.rgb = true;
    for (int i = 0; i < n; ++i) {
        core::CloudPoint p;
        p.position = {float(i % 20), float(i / 20), float(i % 7) * 0.5f};
        p.rgb = core::packRgb(std::uint8_t(i), std::uint8_t(2 * i), std::uint8_t(3 * i));
        p.label = core::Role(i % 3);
        p.range_m = 50.0f + float(i);
        c.points.push_back(p);
    }
    const fs::path path = dir.path / "written.las";
    io::writeCloud(path, c, io::CloudFormat::Las);
    return slurp(path);
}

// Calls fn(record bytes) for each point record of an uncompressed LAS file.
template <typename Fn>
void forEachRecord(std::string& b, Fn fn) {
    const std::size_t at = get<std::uint32_t>(b, 96), record = get<std::uint16_t>(b, 105);
    const std::uint64_t n = get<std::uint64_t>(b, 247);
    for (std::uint64_t i = 0; i < n; ++i) fn(b.data() + at + i * record);
}

}  // namespace

TEST_CASE("las_info: the real surveys of tests/data/real: counts, classes, CRS and units as their README gives") {
    struct Expected {
        const char* file;
        unsigned point_format;
        std::uint64_t points;
        std::map<unsigned, std::uint64_t> classes;  // only those the README counts
        std::vector<unsigned> class_codes;          // every class present
        int epsg;
        const char* horizontal_unit;  // "" when the file states none
        io::ColourDepth colour;
    };
    const Expected files[] = {
        {"4_6_crop.las", 3, 23875, {{1, 14872}, {2, 9003}}, {1, 2}, 2903, "US survey foot", io::ColourDepth::Zero},
        {"sample_c.las", 3, 14408, {{6, 12525}}, {2, 3, 4, 5, 6, 11, 14, 31}, 0, "", io::ColourDepth::SixteenBit},
        {"hexbin-crop.las", 1, 38367, {{1, 3049}, {2, 35318}}, {1, 2}, 32642, "metre", io::ColourDepth::None},
        {"mvk-thin.las", 1, 6280, {}, {1, 2, 4, 5, 9, 12}, 26995, "US survey foot", io::ColourDepth::None},
        {"warsaw_small.las", 3, 3000, {}, {0, 2, 3, 4, 5}, 0, "", io::ColourDepth::SixteenBit},
        {"FSite8_orig-utm.laz", 0, 345966, {{0, 345966}}, {0}, 32632, "metre", io::ColourDepth::None},
    };
    for (const Expected& e : files) {
        CAPTURE(e.file);
        const io::CloudInfo info = io::inspectCloud(kReal / e.file, "info");
        REQUIRE(info.las);
        const io::LasInfo& las = *info.las;
        CHECK(info.format == (std::string(e.file).ends_with(".laz") ? "LAZ" : "LAS"));
        CHECK(info.version == "1.2");
        CHECK(las.point_format == e.point_format);
        CHECK(info.points == e.points);
        CHECK(las.legacy_points == e.points);
        CHECK_FALSE(las.points_64);
        std::vector<unsigned> codes;
        std::uint64_t total = 0;
        for (const auto& [code, n] : las.classes) {
            codes.push_back(code);
            total += n;
        }
        CHECK(codes == e.class_codes);
        CHECK(total == e.points);
        for (const auto& [code, n] : e.classes) CHECK(las.classes.at(code) == n);
        CHECK(las.crs.epsg == e.epsg);
        CHECK(las.crs.horizontal_unit.name == e.horizontal_unit);
        CHECK(las.colour == e.colour);
        CHECK_FALSE(las.copc);
        // The points lie within the header's bounds.
        for (int k = 0; k < 3; ++k) {
            CHECK(las.points_min[k] >= info.min[k] - las.scale[k]);
            CHECK(las.points_max[k] <= info.max[k] + las.scale[k]);
        }
    }
}

TEST_CASE("las_info: what each real file's CRS records say") {
    const io::CloudInfo crop = io::inspectCloud(kReal / "4_6_crop.las", "info");
    CHECK(crop.las->crs.source == "geotiff");
    CHECK(crop.las->crs.vertical_unit.name == "US survey foot");
    CHECK(crop.las->rgb_max == std::array<unsigned, 3>{0, 0, 0});
    const io::CloudInfo hexbin = io::inspectCloud(kReal / "hexbin-crop.las", "info");
    CHECK(hexbin.las->crs.source == "wkt");  // the WKT record is preferred to the GeoTIFF keys
    CHECK(hexbin.las->crs.name == "WGS 84 / UTM zone 42N");
    CHECK(hexbin.las->returns == std::map<unsigned, std::uint64_t>{{4, 38367}});  // ALIRT numbers them so
    CHECK(hexbin.las->records.size() == 4);
    const io::CloudInfo warsaw = io::inspectCloud(kReal / "warsaw_small.las", "info");
    CHECK(warsaw.las->crs.source == "");
    CHECK(warsaw.las->crs.problem == "the WKT record holds no CRS (its text: '')");
    const io::CloudInfo sample = io::inspectCloud(kReal / "sample_c.las", "info");
    CHECK(sample.las->crs.problem == "");
    CHECK(sample.las->records.empty());
    const io::CloudInfo mvk = io::inspectCloud(kReal / "mvk-thin.las", "info");
    CHECK(mvk.las->crs.name == "NAD_1983_StatePlane_Mississippi_West_FIPS_2302_Feet");
    CHECK(mvk.las->crs.vertical_unit.name == "US survey foot");
    CHECK(io::asprsClassName(12, mvk.las->version_minor) == "overlap");  // LAS 1.2's meaning
    CHECK(io::asprsClassName(12, 4) == "reserved");
    CHECK(io::asprsClassName(6, 2) == "building");
    CHECK(io::asprsClassName(40, 4) == "reserved");
    CHECK(io::asprsClassName(64, 4) == "user-defined");
}

TEST_CASE("las_info: colour depth: 16-bit values, 8-bit values in 16-bit fields, all zero") {
    TempDir dir("las_info_colour");
    std::string b = written(dir);
    REQUIRE(b[104] == 7);  // point format 7: RGB at bytes 30..35 of the record
    const io::CloudInfo wide = io::inspectCloud(spit(dir.path / "sixteen.las", b), "info");
    CHECK(wide.las->colour == io::ColourDepth::SixteenBit);
    CHECK(wide.las->rgb_max == std::array<unsigned, 3>{255 * 257, 254 * 257, 255 * 257});
    // Every value <= 255: an 8-bit colour copied into the 16-bit fields as it is.
    forEachRecord(b, [](char* r) {
        for (std::size_t k = 0; k < 3; ++k) {
            std::uint16_t v;
            std::memcpy(&v, r + 30 + 2 * k, 2);
            v = std::uint16_t(v / 257);
            std::memcpy(r + 30 + 2 * k, &v, 2);
        }
    });
    const io::CloudInfo narrow = io::inspectCloud(spit(dir.path / "eight.las", b), "info");
    CHECK(narrow.las->colour == io::ColourDepth::EightBit);
    CHECK(narrow.las->rgb_max == std::array<unsigned, 3>{255, 254, 255});
    // One value of 256 makes them 16-bit again.
    put<std::uint16_t>(b, get<std::uint32_t>(b, 96) + 30 + 2, 256);
    CHECK(io::inspectCloud(spit(dir.path / "one.las", b), "info").las->colour == io::ColourDepth::SixteenBit);
    forEachRecord(b, [](char* r) { std::memset(r + 30, 0, 6); });
    CHECK(io::inspectCloud(spit(dir.path / "zero.las", b), "info").las->colour == io::ColourDepth::Zero);
}

TEST_CASE("las_info: our writer's file: LAS 1.4 counts, extra bytes fields, and any label value counted") {
    TempDir dir("las_info_extra");
    std::string b = written(dir);
    const io::CloudInfo info = io::inspectCloud(spit(dir.path / "ours.las", b), "info");
    const io::LasInfo& las = *info.las;
    CHECK(info.version == "1.4");
    CHECK(las.points_64 == std::optional<std::uint64_t>(500));
    REQUIRE(las.extra_fields.size() == 2);
    CHECK(las.extra_fields[0].name == "range");
    CHECK(las.extra_fields[0].type == "float32");
    CHECK(las.extra_fields[1].name == "label");
    CHECK(las.extra_fields[1].type == "uint8");
    CHECK(info.fields.back() == "label");
    // Roles as ASPRS classes: 2 ground, 1 environment, 64 target (docs/formats.md).
    CHECK(las.classes == std::map<unsigned, std::uint64_t>{{1, 167}, {2, 167}, {64, 166}});
    // A label byte that is none of our roles: the reader refuses it as a cloud, info
    // counts the point as it is.
    const std::size_t label_at = get<std::uint32_t>(b, 96) + 36 + 4;
    b[label_at] = 7;
    const fs::path odd = spit(dir.path / "odd_label.las", b);
    CHECK(errorOf([&] { io::readCloud(odd); }).find("label 7 is not 0 (ground)") != std::string::npos);
    CHECK(io::inspectCloud(odd, "info").points == 500);
}

TEST_CASE("las_info: a COPC file: its format, the nodes of both hierarchy pages, its classes and colours") {
    TempDir dir("las_info_copc");
    const copc_test::File f = copc_test::make();
    const fs::path path = spit(dir.path / "test.copc.laz", f.bytes);
    const io::CloudInfo info = io::inspectCloud(path, "info");
    REQUIRE(info.las);
    CHECK(info.format == "COPC");
    CHECK(info.las->copc);
    CHECK(info.las->copc_nodes == 7);
    CHECK(info.las->compressed);
    std::uint64_t points = 0;
    std::map<unsigned, std::uint64_t> classes;
    unsigned red = 0;
    for (const copc_test::Node& n : f.nodes)
        for (const copc_test::RawPoint& p : n.points) {
            ++points;
            ++classes[p.classification];
            red = std::max<unsigned>(red, p.rgb[0]);
        }
    CHECK(info.points == points);
    CHECK(info.las->classes == classes);
    CHECK(info.las->rgb_max[0] == red);
    // A LAZ file that is not COPC says so.
    const io::CloudInfo laz = io::inspectCloud(kReal / "FSite8_orig-utm.laz", "info");
    CHECK(laz.format == "LAZ");
    CHECK_FALSE(laz.las->copc);
}

TEST_CASE("las_info: a truncated file and a VLR past the point data are refused in one line") {
    TempDir dir("las_info_bad");
    const std::string crop = slurp(kReal / "4_6_crop.las");
    REQUIRE(crop.size() == 812210);
    const fs::path cut = spit(dir.path / "cut.las", crop.substr(0, 400000));
    const std::string data_bytes = std::to_string(400000 - get<std::uint32_t>(crop, 96));
    CHECK(errorOf([&] { io::inspectCloud(cut, "info"); }) ==
          "info: " + cut.string() + ": truncated: the header says 23875 points of 34 bytes but only " + data_bytes +
              " bytes of point data follow");
    const fs::path header_only = spit(dir.path / "header.las", crop.substr(0, 100));
    CHECK(errorOf([&] { io::inspectCloud(header_only, "info"); }) ==
          "info: " + header_only.string() + ": truncated: a LAS header needs 227 bytes, the file has 100");
    // VLR 1 (the GeoTIFF ASCII params) declares more bytes than lie before the points.
    std::string b = crop;
    const std::size_t first = get<std::uint16_t>(b, 94);
    const std::size_t second = first + 54 + get<std::uint16_t>(b, first + 20);
    put<std::uint16_t>(b, second + 20, 60000);
    const fs::path long_vlr = spit(dir.path / "long_vlr.las", b);
    CHECK(errorOf([&] { io::inspectCloud(long_vlr, "info"); }) ==
          "info: " + long_vlr.string() + ": VLR 1 runs into the point data");
    CHECK(errorOf([&] { io::inspectCloud(dir.path / "absent.las", "info"); }) ==
          "info: " + (dir.path / "absent.las").string() + ": file does not exist");
}
