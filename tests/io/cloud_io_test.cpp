// Cloud I/O: exact round trips of every format, atomic streaming writes, files written
// by PCL (ascii, binary, binary_compressed), foreign layouts, and corrupt input.
#include <test_files.hpp>
#include <test_paths.hpp>
#include <core/error.hpp>
#include <io/cloud_io.hpp>
#include <platform/atomic_file.hpp>

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <future>
#include <random>
#include <span>
#include <sstream>
#include <stdexcept>
#include <string>

#include <unistd.h>

namespace fs = std::filesystem;
using core::Role;
using io::CloudFormat;

namespace {

const fs::path kData = fs::path(test_support::dataDir()) / "io";

using test_support::slurp;
using test_support::TempDir;

void spit(const fs::path& p, const std::string& bytes) { std::ofstream(p, std::ios::binary) << bytes; }

// Points that exercise every field's corners: awkward floats, every label, the view
// extremes, colours whose packed float is a denormal (red < 0x80) or zero.
core::PointCloud awkwardCloud() {
    core::PointCloud c;
    c.origin = {1234567.891011, -9876543.21, 10000000.125};
    const float specials[] = {0.0f, -0.0f,       1e-7f,       -3.4e38f, 3.4e38f,
                              0.1f, 1.0f / 3.0f, 123456.789f, -1e-38f,  2.5e-42f /* denormal */};
    std::mt19937 rng(42);
    for (int i = 0; i < 500; ++i) {
        core::CloudPoint p;
        if (i < 10) {
            p.position = {specials[i], specials[(i + 3) % 10], specials[(i + 7) % 10]};
        } else {
            std::uniform_real_distribution<float> d(-300.0f, 300.0f);
            p.position = {d(rng), d(rng), d(rng)};
        }
        const std::uint32_t colours[] = {0x000000u, 0xFFFFFFu, 0x7F0000u, 0x00007Fu, 0x800001u};
        p.rgb = i < 5 ? colours[i] : std::uint32_t(rng()) & 0xFFFFFFu;
        p.label = Role(i % 3);
        p.view = i == 0 ? 0 : i == 1 ? 65535 : std::uint16_t(rng());
        p.range_m = i == 2 ? 0.0f : std::uniform_real_distribution<float>(0.0f, 1000.0f)(rng);
        c.points.push_back(p);
    }
    return c;
}

bool samePoint(const core::CloudPoint& a, const core::CloudPoint& b, const core::CloudFields& f) {
    // Bitwise equality for positions (keeps -0.0 and denormals honest).
    if (std::memcmp(&a.position, &b.position, sizeof a.position) != 0) return false;
    if (f.rgb && a.rgb != b.rgb) return false;
    if (f.label && a.label != b.label) return false;
    if (f.view && a.view != b.view) return false;
    if (f.range && std::memcmp(&a.range_m, &b.range_m, 4) != 0) return false;
    return true;
}

std::size_t firstMismatch(const core::PointCloud& a, const core::PointCloud& b) {
    for (std::size_t i = 0; i < a.points.size(); ++i)
        if (!samePoint(a.points[i], b.points[i], a.fields)) return i;
    return a.points.size();
}

std::string readError(const fs::path& p) {
    try {
        io::readCloud(p);
    } catch (const core::Error& e) {
        return e.what();
    }
    FAIL("no error reading " << p.string());
    return {};
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

const CloudFormat kAllFormats[] = {CloudFormat::PcdBinary, CloudFormat::PcdAscii, CloudFormat::PlyBinary,
                                   CloudFormat::PlyAscii};

const char* extensionOf(CloudFormat f) {
    return f == CloudFormat::PlyBinary || f == CloudFormat::PlyAscii ? ".ply" : ".pcd";
}

}  // namespace

TEST_CASE("cloud_io: format names and defaults") {
    CHECK(io::parseCloudFormat("pcd", "--format") == CloudFormat::PcdBinary);
    CHECK(io::parseCloudFormat("pcd-ascii", "--format") == CloudFormat::PcdAscii);
    CHECK(io::parseCloudFormat("ply", "--format") == CloudFormat::PlyBinary);
    CHECK(io::parseCloudFormat("ply-ascii", "--format") == CloudFormat::PlyAscii);
    CHECK(io::parseCloudFormat("las", "--format") == CloudFormat::Las);
    CHECK(io::parseCloudFormat("laz", "--format") == CloudFormat::Laz);
    CHECK_THROWS_WITH_AS(io::parseCloudFormat("e57", "--format"),
                         "--format: format 'e57' is not one of pcd, pcd-ascii, ply, ply-ascii, las, laz, copc",
                         core::Error);
    CHECK(io::formatForPath("a/b.ply") == CloudFormat::PlyBinary);
    CHECK(io::formatForPath("a/b.PLY") == CloudFormat::PlyBinary);
    CHECK(io::formatForPath("a/b.pcd") == CloudFormat::PcdBinary);
    CHECK(io::formatForPath("a/b") == CloudFormat::PcdBinary);
    CHECK(io::formatForPath("a/b.las") == CloudFormat::Las);
    CHECK(io::formatForPath("a/b.LAZ") == CloudFormat::Laz);
    // A name we cannot write is refused, never filled with another format.
    CHECK_THROWS_WITH_AS(io::formatForPath("a/b.e57", "--out"),
                         "--out: a/b.e57: extension '.e57' is not one of .pcd, .ply, .las, .laz, .copc.laz",
                         core::Error);
    CHECK_THROWS_AS(io::formatForPath("a/cloud.txt"), core::Error);
}

TEST_CASE("cloud_io: every format round-trips every field and the origin exactly") {
    TempDir dir("roundtrip");
    const core::PointCloud c = awkwardCloud();
    for (CloudFormat f : kAllFormats) {
        CAPTURE(int(f));
        const fs::path p = dir.path / ("cloud" + std::to_string(int(f)) + extensionOf(f));
        io::writeCloud(p, c, f);
        const core::PointCloud r = io::readCloud(p);
        CHECK(r.origin == c.origin);  // exact doubles through %.17g
        CHECK(r.fields.rgb);
        CHECK(r.fields.label);
        CHECK(r.fields.view);
        CHECK(r.fields.range);
        REQUIRE(r.points.size() == c.points.size());
        CHECK(firstMismatch(c, r) == c.points.size());
    }
    CHECK(dir.entries() == 4);  // no temporary files left behind
}

TEST_CASE("cloud_io: the origin survives at 1e6 and 1e7 m") {
    TempDir dir("origin");
    for (double base : {1e6, 1e7, -1e7}) {
        core::PointCloud c;
        c.origin = {base + 0.123456789, base * 0.5 + 0.987654321, 123.456};
        core::CloudPoint p;
        p.position = {0.01f, -0.02f, 0.03f};
        c.points.push_back(p);
        for (CloudFormat f : kAllFormats) {
            const fs::path path = dir.path / (std::string("o") + extensionOf(f));
            io::writeCloud(path, c, f);
            const core::PointCloud r = io::readCloud(path);
            CHECK(r.origin == c.origin);
            // world = origin + local keeps the centimetre.
            CHECK(r.origin.x + double(r.points.at(0).position.x) == doctest::Approx(base + 0.133456789).epsilon(1e-15));
        }
    }
}

TEST_CASE("cloud_io: optional fields are written and read only when present") {
    TempDir dir("fields");
    core::PointCloud c = awkwardCloud();
    c.fields = {};
    c.fields.rgb = false;
    c.fields.view = false;
    for (CloudFormat f : kAllFormats) {
        const fs::path p = dir.path / (std::string("f") + extensionOf(f));
        io::writeCloud(p, c, f);
        const std::string text = slurp(p);
        CHECK_FALSE(contains(text.substr(0, 600), "view"));
        CHECK_FALSE(contains(text.substr(0, 600), "rgb"));
        CHECK_FALSE(contains(text.substr(0, 600), "red"));
        const core::PointCloud r = io::readCloud(p);
        CHECK_FALSE(r.fields.rgb);
        CHECK_FALSE(r.fields.view);
        CHECK(r.fields.label);
        CHECK(r.fields.range);
        REQUIRE(r.points.size() == c.points.size());
        CHECK(firstMismatch(c, r) == c.points.size());
        CHECK(r.points[7].rgb == core::kWhite);  // the default when absent
        CHECK(r.points[7].view == 0);
    }
}

TEST_CASE("cloud_io: the binary PCD header is PCL's, with the counts fixed up in place") {
    TempDir dir("header");
    core::PointCloud c = awkwardCloud();
    c.points.resize(123);
    const fs::path p = dir.path / "h.pcd";
    io::writeCloud(p, c, CloudFormat::PcdBinary);
    const std::string text = slurp(p);
    char origin[128];
    std::snprintf(origin, sizeof origin, "%.17g %.17g %.17g", c.origin.x, c.origin.y, c.origin.z);
    CHECK(contains(text, "\n# ladarvr origin " + std::string(origin) + "\n"));
    CHECK(contains(text,
                   "\nFIELDS x y z rgb label view range\nSIZE 4 4 4 4 1 2 4\n"
                   "TYPE F F F F U U F\nCOUNT 1 1 1 1 1 1 1\n"));
    CHECK(contains(text, "\nWIDTH 000000000123\nHEIGHT 1\n"));
    CHECK(contains(text, "\nPOINTS 000000000123\nDATA binary\n"));
    const std::size_t data = text.find("DATA binary\n") + 12;
    CHECK(text.size() - data == 123u * 23u);
    // Record 4: x y z, then rgb as PCL's packed float (0x800001), label, view, range.
    const char* rec = text.data() + data + 4 * 23;
    std::uint32_t rgb;
    std::memcpy(&rgb, rec + 12, 4);
    CHECK(rgb == 0x800001u);
    CHECK(std::uint8_t(rec[16]) == 1);  // label of point 4 = 4 % 3

    const fs::path q = dir.path / "h.ply";
    io::writeCloud(q, c, CloudFormat::PlyBinary);
    const std::string ply = slurp(q);
    CHECK(ply.rfind("ply\nformat binary_little_endian 1.0\n", 0) == 0);
    CHECK(contains(ply, "\ncomment ladarvr origin " + std::string(origin) + "\n"));
    CHECK(contains(ply, "element vertex 000000000123\n"));
    // scalar_* names and uchar/int/float types: CloudCompare and Open3D keep them all.
    CHECK(contains(ply,
                   "property uchar red\nproperty uchar green\nproperty uchar blue\n"
                   "property uchar scalar_label\nproperty int scalar_view\nproperty float scalar_range\n"
                   "end_header\n"));
    CHECK(ply.size() - (ply.find("end_header\n") + 11) == 123u * 24u);
}

TEST_CASE("cloud_io: CloudWriter streams many chunks and counts them") {
    TempDir dir("stream");
    const fs::path p = dir.path / "big.pcd";
    io::CloudWriter w(p, CloudFormat::PcdBinary, {1.0, 2.0, 3.0});
    // 600k points in uneven chunks: several internal flushes.
    std::vector<core::CloudPoint> chunk;
    std::size_t total = 0;
    for (int c = 0; c < 7; ++c) {
        chunk.assign(std::size_t(40000 + 20000 * c), core::CloudPoint{});
        for (std::size_t i = 0; i < chunk.size(); ++i) {
            chunk[i].position.x = float(total + i);
            chunk[i].view = std::uint16_t(c);
        }
        w.append(chunk);
        total += chunk.size();
    }
    CHECK(w.count() == total);
    CHECK_FALSE(fs::exists(p));  // nothing under the final name before commit
    w.commit();
    const core::PointCloud r = io::readCloud(p);
    REQUIRE(r.points.size() == total);
    CHECK(r.points.front().position.x == 0.0f);
    CHECK(r.points.back().position.x == float(total - 1));
    CHECK(r.points.back().view == 6);
    CHECK(r.origin == glm::dvec3(1.0, 2.0, 3.0));
    CHECK(dir.entries() == 1);
}

// Every field of a point, bit for bit.
bool sameEveryField(const core::CloudPoint& a, const core::CloudPoint& b) { return std::memcmp(&a, &b, sizeof a) == 0; }

namespace {

// Every optional field on, 20,000 points: more than one system call's records and more
// than one flush of a writer's buffer.
core::PointCloud everyFieldCloud() {
    core::PointCloud c;
    c.origin = {651000.5, 6862000.25, 85.0};
    c.fields = {};
    c.fields.intensity = c.fields.returns = c.fields.incidence = c.fields.scan_angle = true;
    c.fields.height_above_ground = true;
    const core::PointCloud awkward = awkwardCloud();
    for (std::size_t i = 0; i < 20000; ++i) {
        core::CloudPoint p = awkward.points[i % awkward.points.size()];
        p.position.x += float(i);
        p.intensity = std::uint16_t(i * 7);
        p.return_number = std::uint8_t(1 + i % 3);
        p.returns = 3;
        p.incidence_deg = float(i % 90) + 0.125f;
        p.scan_angle_deg = -float(i % 30) - 0.5f;
        p.height_above_ground_m = float(i) * 1e-3f;
        c.points.push_back(p);
    }
    return c;
}

}  // namespace

TEST_CASE("cloud_io: binary PCD and PLY read their points back and rewrite them in place before commit") {
    TempDir dir("rewrite");
    const core::PointCloud c = everyFieldCloud();
    for (const CloudFormat f : {CloudFormat::PcdBinary, CloudFormat::PlyBinary}) {
        CAPTURE(int(f));
        const fs::path p = dir.path / (std::string("r") + extensionOf(f));
        io::CloudWriter w(p, f, c.origin, c.fields);
        CHECK(w.rewritable());
        CHECK(w.recordBytes() == (f == CloudFormat::PcdBinary ? 12 + 4 + 1 + 2 + 4 + 2 + 1 + 1 + 4 + 4 + 4
                                                              : 12 + 3 + 1 + 4 + 4 + 4 + 1 + 1 + 4 + 4 + 4));
        const std::size_t first_part = 15000;
        w.append(std::span(c.points).first(first_part));

        // Everything appended comes back as it went in, whatever the range.
        std::vector<core::CloudPoint> back(first_part + 100);
        REQUIRE(w.readBack(0, back) == first_part);
        std::size_t differ = 0;
        for (std::size_t i = 0; i < first_part; ++i) differ += !sameEveryField(back[i], c.points[i]);
        CHECK(differ == 0);
        CHECK(w.readBack(first_part - 10, std::span(back).first(100)) == 10);
        CHECK(sameEveryField(back[9], c.points[first_part - 1]));
        CHECK(w.readBack(first_part, back) == 0);

        // Rewrite two ranges at once from two threads while a third range is read back,
        // then append the rest: the file is the one written in one go.
        core::PointCloud expected = c;
        for (std::size_t i = 0; i < first_part; ++i) {
            expected.points[i].rgb = std::uint32_t(i * 2654435761u) & 0xFFFFFFu;
            expected.points[i].height_above_ground_m = -float(i);
        }
        const std::span<const core::CloudPoint> all(expected.points);
        auto other = std::async(std::launch::async, [&] { w.rewrite(5000, all.subspan(5000, 10000)); });
        std::vector<core::CloudPoint> middle(100);
        w.rewrite(0, all.first(2500));
        CHECK(w.readBack(2500, middle) == 100);  // not rewritten yet: as appended
        CHECK(sameEveryField(middle[0], c.points[2500]));
        other.get();
        w.rewrite(2500, all.subspan(2500, 2500));
        CHECK_THROWS_AS(w.rewrite(first_part - 1, all.subspan(0, 2)), std::logic_error);  // past the points
        w.append(all.subspan(first_part));
        CHECK(w.readBack(19999, std::span(back).first(1)) == 1);
        CHECK(sameEveryField(back[0], expected.points[19999]));
        w.commit();
        CHECK_THROWS_AS(w.readBack(0, back), core::Error);  // after commit

        const fs::path q = dir.path / (std::string("once") + extensionOf(f));
        io::writeCloud(q, expected, f);
        CHECK(slurp(p) == slurp(q));
    }
    // Text and LAS records cannot be rewritten in place.
    for (const CloudFormat f : {CloudFormat::PcdAscii, CloudFormat::PlyAscii, CloudFormat::Las}) {
        CAPTURE(int(f));
        io::CloudWriter w(dir.path / (f == CloudFormat::Las ? std::string("t.las") : std::string("t") + extensionOf(f)),
                          f, c.origin, c.fields);
        std::vector<core::CloudPoint> back(10);
        w.append(back);
        CHECK_FALSE(w.rewritable());
        CHECK(w.recordBytes() == 0);
        CHECK_THROWS_AS(w.readBack(0, back), std::logic_error);
        CHECK_THROWS_AS(w.rewrite(0, back), std::logic_error);
    }
}

TEST_CASE("cloud_io: records packed on other threads and appended make the file append() makes") {
    TempDir dir("packed");
    const core::PointCloud c = everyFieldCloud();
    for (const CloudFormat f : {CloudFormat::PcdBinary, CloudFormat::PlyBinary}) {
        CAPTURE(int(f));
        const fs::path p = dir.path / (std::string("packed") + extensionOf(f));
        io::CloudWriter w(p, f, c.origin, c.fields);
        const std::size_t size = w.recordBytes();
        REQUIRE(size > 0);
        // Points appended as points, then two runs packed at once on two threads and
        // appended in order, then points again, then an empty run.
        const std::span<const core::CloudPoint> all(c.points);
        w.append(all.first(3000));
        std::vector<char> a(9000 * size), b(8000 * size);
        auto other = std::async(std::launch::async, [&] { w.packRecords(all.subspan(3000, 9000), a.data()); });
        w.packRecords(all.subspan(12000, 8000), b.data());
        other.get();
        w.appendRecords(a);
        CHECK(w.count() == 12000);
        CHECK_THROWS_AS(w.appendRecords(std::span(b).first(size + 1)), std::logic_error);  // not whole records
        CHECK(w.count() == 12000);
        w.appendRecords(b);
        w.appendRecords({});
        CHECK(w.count() == 20000);
        std::vector<core::CloudPoint> back(1);
        REQUIRE(w.readBack(12345, back) == 1);
        CHECK(sameEveryField(back[0], c.points[12345]));
        w.commit();
        const fs::path q = dir.path / (std::string("once") + extensionOf(f));
        io::writeCloud(q, c, f);
        CHECK(slurp(p) == slurp(q));
    }
    // Records packed apart come from the binary PCD and PLY writers alone.
    for (const CloudFormat f : {CloudFormat::PcdAscii, CloudFormat::Laz}) {
        CAPTURE(int(f));
        io::CloudWriter w(dir.path / (f == CloudFormat::Laz ? std::string("t.laz") : std::string("t") + extensionOf(f)),
                          f, c.origin, c.fields);
        std::vector<char> bytes(64);
        CHECK_THROWS_AS(w.packRecords(std::span(c.points).first(1), bytes.data()), std::logic_error);
        CHECK_THROWS_AS(w.appendRecords(bytes), std::logic_error);
        CHECK(w.count() == 0);
    }
}

TEST_CASE("cloud_io: a CloudWriter destroyed without commit leaves nothing behind") {
    TempDir dir("nocommit");
    const core::PointCloud c = awkwardCloud();
    SUBCASE("no file before") {
        const fs::path p = dir.path / "out.pcd";
        {
            io::CloudWriter w(p, CloudFormat::PcdBinary, c.origin);
            w.append(c.points);
            CHECK(dir.entries() == 1);  // the temporary, under its own name
        }
        CHECK_FALSE(fs::exists(p));
        CHECK(dir.entries() == 0);
    }
    SUBCASE("an existing file stays untouched") {
        const fs::path p = dir.path / "out.ply";
        spit(p, "previous result");
        {
            io::CloudWriter w(p, CloudFormat::PlyBinary, c.origin);
            w.append(c.points);
        }
        CHECK(slurp(p) == "previous result");
        CHECK(dir.entries() == 1);
    }
    SUBCASE("an exception mid-run unwinds the writer") {
        const fs::path p = dir.path / "out.pcd";
        try {
            io::CloudWriter w(p, CloudFormat::PcdAscii, c.origin);
            w.append(c.points);
            throw core::Error("sim: something failed");
        } catch (const core::Error&) {}
        CHECK(dir.entries() == 0);
    }
}

TEST_CASE("cloud_io: unwritable destinations fail before any work") {
    TempDir dir("dest");
    CHECK_THROWS_WITH_AS(io::CloudWriter(dir.path / "missing" / "out.pcd", CloudFormat::PcdBinary, {}),
                         ("output: " + (dir.path / "missing" / "out.pcd").string() + ": directory '" +
                          (dir.path / "missing").string() + "' does not exist")
                             .c_str(),
                         core::Error);
    CHECK_THROWS_WITH_AS(io::CloudWriter(dir.path, CloudFormat::PcdBinary, {}), doctest::Contains("is a directory"),
                         core::Error);
    CHECK_THROWS_WITH_AS(io::CloudWriter(dir.path / "o.pcd", CloudFormat::PcdBinary, {std::nan(""), 0.0, 0.0}),
                         doctest::Contains("origin is not finite"), core::Error);
    CHECK(dir.entries() == 0);
}

TEST_CASE("cloud_io: files written by PCL read back with their known values") {
    // Made by PCL 1.15's pcl_convert_pcd_ascii_binary from one ASCII file: point i has
    // x = i/4, y = -1.5 (i % 17), z = (i / 10) / 2, rgb = (i, 7i, 13i) mod 256,
    // label = i % 3, view = 11 i, range = 100 + i/8.
    for (const char* name : {"pcl_ascii.pcd", "pcl_binary.pcd", "pcl_binary_compressed.pcd"}) {
        CAPTURE(name);
        const core::PointCloud r = io::readCloud(kData / name);
        REQUIRE(r.points.size() == 300);
        CHECK(r.fields.rgb);
        CHECK(r.fields.label);
        CHECK(r.fields.view);
        CHECK(r.fields.range);
        std::size_t bad = 0;
        for (std::size_t i = 0; i < 300; ++i) {
            const core::CloudPoint& p = r.points[i];
            const bool ok =
                p.position == glm::vec3(float(i) * 0.25f, -float(i % 17) * 1.5f, float(i / 10) * 0.5f) &&
                p.rgb == core::packRgb(std::uint8_t(i % 256), std::uint8_t(i * 7 % 256), std::uint8_t(i * 13 % 256)) &&
                p.label == Role(i % 3) && p.view == i * 11 && p.range_m == 100.0f + float(i) * 0.125f;
            if (!ok && bad++ == 0) CAPTURE(i);
        }
        CHECK(bad == 0);
    }
}

TEST_CASE("cloud_io: foreign layouts: x y z only, rgba, padding fields, doubles, organised") {
    TempDir dir("foreign");
    SUBCASE("PCD with only x y z and no COUNT") {
        const fs::path p = dir.path / "xyz.pcd";
        spit(p,
             "VERSION .7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 2\nHEIGHT 1\n"
             "POINTS 2\nDATA ascii\n1 2 3\n4 5 6\n");
        const core::PointCloud r = io::readCloud(p);
        CHECK_FALSE(r.fields.rgb);
        CHECK_FALSE(r.fields.label);
        CHECK(r.origin == glm::dvec3(0.0));
        REQUIRE(r.points.size() == 2);
        CHECK(r.points[1].position == glm::vec3(4, 5, 6));
        CHECK(r.points[1].rgb == core::kWhite);
    }
    SUBCASE("binary PCD with doubles, rgba as U, an array field and an organised 2 x 2 grid") {
        std::string body;
        auto put = [&](const void* v, std::size_t n) { body.append(static_cast<const char*>(v), n); };
        for (int i = 0; i < 4; ++i) {
            const double xyz[3] = {i + 0.5, -i * 2.0, 1e6 + i};
            const float normal[3] = {0.f, 0.f, 1.f};
            const std::uint32_t rgba = 0xFF000000u | std::uint32_t(0x102030 * i);
            put(xyz, 24);
            put(normal, 12);
            put(&rgba, 4);
        }
        const fs::path p = dir.path / "org.pcd";
        spit(p,
             "# from elsewhere\nVERSION 0.7\nFIELDS x y z normal rgba\nSIZE 8 8 8 4 4\n"
             "TYPE F F F F U\nCOUNT 1 1 1 3 1\nWIDTH 2\nHEIGHT 2\nVIEWPOINT 0 0 0 1 0 0 0\n"
             "POINTS 4\nDATA binary\n" +
                 body);
        const core::PointCloud r = io::readCloud(p);
        REQUIRE(r.points.size() == 4);
        CHECK(r.fields.rgb);
        // Doubles move onto a double origin (whole metres of the first point) first.
        CHECK(r.origin == glm::dvec3(0.0, 0.0, 1e6));
        CHECK(r.points[3].position == glm::vec3(3.5f, -6.0f, 3.0f));
        CHECK(r.points[3].rgb == 0x306090u);
    }
    SUBCASE("PLY big endian with doubles, float colours, and a face element first") {
        std::string body;
        auto be = [&](const void* v, std::size_t n) {
            std::string b(static_cast<const char*>(v), n);
            std::reverse(b.begin(), b.end());
            body += b;
        };
        // face element: one triangle (uchar count, int indices)
        body += char(3);
        for (std::int32_t k : {0, 1, 2}) be(&k, 4);
        for (int i = 0; i < 3; ++i) {
            const double xyz[3] = {double(i), 2.0 * i, -1.0};
            for (double d : xyz) be(&d, 8);
            const float col[3] = {1.0f, 0.5f, 0.0f};
            for (float f : col) be(&f, 4);
            const std::uint16_t view = std::uint16_t(300 + i);
            be(&view, 2);
        }
        const fs::path p = dir.path / "be.ply";
        spit(p,
             "ply\nformat binary_big_endian 1.0\nobj_info x\nelement face 1\n"
             "property list uchar int vertex_indices\nelement vertex 3\nproperty double x\n"
             "property double y\nproperty double z\nproperty float red\nproperty float green\n"
             "property float blue\nproperty ushort view\nend_header\n" +
                 body);
        const core::PointCloud r = io::readCloud(p);
        REQUIRE(r.points.size() == 3);
        CHECK(r.points[2].position == glm::vec3(2, 4, -1));
        CHECK(r.points[2].rgb == core::packRgb(255, 128, 0));
        CHECK(r.points[2].view == 302);
        CHECK(r.fields.view);
        CHECK_FALSE(r.fields.label);
    }
    SUBCASE("ASCII PLY with an element after the vertices") {
        const fs::path p = dir.path / "a.ply";
        spit(p,
             "ply\r\nformat ascii 1.0\r\nelement vertex 2\r\nproperty float x\r\n"
             "property float y\r\nproperty float z\r\nproperty uchar label\r\n"
             "element face 1\r\nproperty list uchar int vertex_indices\r\nend_header\r\n"
             "1 2 3 2\r\n4 5 6 0\r\n3 0 1 1\r\n");
        const core::PointCloud r = io::readCloud(p);
        REQUIRE(r.points.size() == 2);
        CHECK(r.points[0].label == Role::Target);
        CHECK(r.points[1].position == glm::vec3(4, 5, 6));
    }
}

TEST_CASE("cloud_io: truncated and corrupt files give a clear error") {
    TempDir dir("corrupt");
    core::PointCloud c = awkwardCloud();
    c.points.resize(50);
    const fs::path good_bin = dir.path / "good.pcd";
    const fs::path good_ascii = dir.path / "good_ascii.pcd";
    const fs::path good_ply = dir.path / "good.ply";
    const fs::path good_ply_ascii = dir.path / "good_ascii.ply";
    io::writeCloud(good_bin, c, CloudFormat::PcdBinary);
    io::writeCloud(good_ascii, c, CloudFormat::PcdAscii);
    io::writeCloud(good_ply, c, CloudFormat::PlyBinary);
    io::writeCloud(good_ply_ascii, c, CloudFormat::PlyAscii);
    const fs::path p = dir.path / "bad.pcd";
    const std::string pre = "pcd: " + p.string() + ": ";

    SUBCASE("missing file") {
        CHECK(readError(dir.path / "none.pcd") == "pcd: " + (dir.path / "none.pcd").string() + ": file does not exist");
    }
    SUBCASE("binary PCD cut short") {
        const std::string t = slurp(good_bin);
        spit(p, t.substr(0, t.size() - 10));
        CHECK(readError(p) == pre + "truncated: the header says 50 points of 23 bytes but only " +
                                  std::to_string(50 * 23 - 10) + " bytes of data follow the header");
    }
    SUBCASE("ASCII PCD cut short") {
        const std::string t = slurp(good_ascii);
        spit(p, t.substr(0, t.size() / 2));
        const std::string m = readError(p);
        CHECK(contains(m, pre + "truncated: the header says 50 points but the data end at line"));
    }
    SUBCASE("PCD header without DATA") {
        spit(p, "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 1\n");
        CHECK(readError(p) == pre + "the header ends without a DATA line; not a PCD file?");
    }
    SUBCASE("PCD header inconsistencies") {
        spit(p, "FIELDS x y z\nSIZE 4 4\nTYPE F F F\nWIDTH 1\nDATA ascii\n1 2 3\n");
        CHECK(readError(p) == pre + "SIZE has 2 entries but FIELDS has 3");
        spit(p, "FIELDS x y z\nSIZE 4 4 4\nTYPE F F Q\nWIDTH 1\nDATA ascii\n1 2 3\n");
        CHECK(readError(p) == pre + "line 3: TYPE 'Q' is not one of F, U, I");
        spit(p, "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH -1\nDATA ascii\n1 2 3\n");
        CHECK(readError(p) == pre + "line 4: WIDTH needs one non-negative integer");
        spit(p, "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 2\nPOINTS 3\nDATA ascii\n1 2 3\n");
        CHECK(readError(p) == pre + "POINTS 3 is not WIDTH x HEIGHT = 2");
        spit(p, "FIELDS x y intensity\nSIZE 4 4 4\nTYPE F F F\nWIDTH 1\nDATA ascii\n1 2 3\n");
        CHECK(readError(p) == pre + "FIELDS has no x, y and z; they are required");
        spit(p, "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 1\nDATA lzma\n");
        CHECK(readError(p) == pre + "line 5: DATA must be one of ascii, binary, binary_compressed");
        spit(p, "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 1\nDATA ascii\n1 two 3\n");
        CHECK(readError(p) == pre + "line 6: value 'two' of point 0 is not a number");
        spit(p,
             "# ladarvr origin 0 0 0\nFIELDS x y z label\nSIZE 4 4 4 1\nTYPE F F F U\nWIDTH 1\nDATA ascii\n1 2 3 7\n");
        CHECK(readError(p) == pre + "point 0: label 7 is not 0 (ground), 1 (environment) or 2 (target)");
        spit(p, "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 99999999999\nDATA binary\n");
        CHECK(contains(readError(p), "truncated: the header says 99999999999 points"));
    }
    SUBCASE("binary_compressed cut short or corrupt") {
        const std::string t = slurp(kData / "pcl_binary_compressed.pcd");
        const std::size_t data = t.find("DATA binary_compressed\n") + 23;
        spit(p, t.substr(0, data + 5));
        CHECK(readError(p) == pre + "truncated: binary_compressed data need an 8-byte size header");
        spit(p, t.substr(0, data + 100));
        CHECK(contains(readError(p), pre + "truncated: the compressed block is "));
        std::string corrupt = t;
        corrupt[data + 8] = char(0xFF);  // the first control byte: a back reference to nothing
        spit(p, corrupt);
        CHECK(readError(p) == pre + "binary_compressed: the LZF data are corrupt");
        std::string huge = t;
        const std::uint32_t claim = 0x7FFFFFFF;
        std::memcpy(huge.data() + data + 4, &claim, 4);
        spit(p, huge);
        CHECK(contains(readError(p), "binary_compressed: the uncompressed size 2147483647 is not"));
    }
    SUBCASE("PLY cut short and bad headers") {
        const fs::path q = dir.path / "bad.ply";
        const std::string qpre = "ply: " + q.string() + ": ";
        const std::string t = slurp(good_ply);
        spit(q, t.substr(0, t.size() - 1));
        CHECK(readError(q) == qpre + "truncated: the header says 50 vertices of 24 bytes but only " +
                                  std::to_string(50 * 24 - 1) + " bytes of data follow");
        const std::string a = slurp(good_ply_ascii);
        spit(q, a.substr(0, a.size() - 30));
        CHECK(contains(readError(q), qpre + "truncated: the header says 50 points"));
        spit(q, "ply\nformat binary_middle_endian 1.0\nend_header\n");
        CHECK(readError(q) == qpre +
                                  "line 2: format must be one of ascii, binary_little_endian, "
                                  "binary_big_endian (version 1.0)");
        spit(q, "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty quad y\nend_header\n");
        CHECK(readError(q) == qpre +
                                  "line 5: property type 'quad' is not one of char, uchar, "
                                  "short, ushort, int, uint, float, double");
        spit(q, "ply\nformat ascii 1.0\nelement face 1\nproperty uchar x\nend_header\n1\n");
        CHECK(readError(q) == qpre + "the header has no 'element vertex'");
        spit(q, "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n");
        CHECK(readError(q) == qpre + "the header ends without 'end_header'");
    }
}

TEST_CASE("cloud_io: readCloudData parses bytes in memory") {
    const std::string pcd =
        "# ladarvr origin 1 2 3\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\n"
        "WIDTH 1\nDATA ascii\n4 5 6\n";
    const core::PointCloud r = io::readCloudData(pcd, "mem.pcd");
    CHECK(r.origin == glm::dvec3(1, 2, 3));
    REQUIRE(r.points.size() == 1);
    CHECK(r.points[0].position == glm::vec3(4, 5, 6));
    CHECK_THROWS_WITH_AS(io::readCloudData(std::string_view(pcd).substr(0, 20), "mem.pcd"),
                         doctest::Contains("pcd: mem.pcd: "), core::Error);
    CHECK_THROWS_WITH_AS(io::readCloudData("", "empty.ply"),
                         "pcd: empty.ply: the header ends without a DATA line; not a PCD file?", core::Error);
}

TEST_CASE("cloud_io: mutated files never crash the reader") {
    // A small deterministic fuzz: random byte edits, insertions and cuts of valid files
    // must give a cloud or an core::Error, nothing else (run under ASan in CI).
    TempDir dir("mutate");
    core::PointCloud c = awkwardCloud();
    c.points.resize(20);
    std::vector<std::string> seeds;
    for (CloudFormat f : kAllFormats) {
        const fs::path p = dir.path / (std::string("seed") + extensionOf(f));
        io::writeCloud(p, c, f);
        seeds.push_back(slurp(p));
    }
    seeds.push_back(slurp(kData / "pcl_binary_compressed.pcd"));
    std::mt19937 rng(7);
    int parsed = 0, rejected = 0;
    for (int iter = 0; iter < 3000; ++iter) {
        std::string s = seeds[std::size_t(iter) % seeds.size()];
        const int edits = 1 + int(rng() % 4);
        for (int e = 0; e < edits; ++e) {
            const std::size_t at = rng() % s.size();
            switch (rng() % 5) {
                case 0: s[at] = char(rng()); break;
                case 1: s[at] = "0123456789 \n-e."[rng() % 15]; break;
                case 2: s.insert(at, 1, char(rng())); break;
                case 3: s.erase(at, 1 + rng() % 8); break;
                default: s.resize(at + 1); break;
            }
            if (s.empty()) s = "x";
        }
        // A new name each time: rewriting one file in place makes ext4 flush it (slow).
        const fs::path p = dir.path / ("m" + std::to_string(iter));
        spit(p, s);
        try {
            io::readCloud(p);
            ++parsed;
        } catch (const core::Error&) {
            ++rejected;
        }
        fs::remove(p);
    }
    CHECK(parsed + rejected == 3000);
    CHECK(rejected > 100);
}
