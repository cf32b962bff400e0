// LAS/LAZ and the optional Ladar fields: exact round trips of intensity, returns,
// incidence, scan angle and height above ground through PCD, PLY, LAS and LAZ; LAS
// classes, GPS time and point format; georeferenced doubles at 10^7 m within 1 mm in
// every reader; ASPRS labels; bad LAS files refused with one line.
#include <test_files.hpp>
#include <core/error.hpp>
#include <io/cloud_io.hpp>
#include <io/cloud_reader.hpp>

#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <string>

namespace fs = std::filesystem;
using core::Role;
using io::CloudFormat;

namespace {

using test_support::slurp;
using test_support::TempDir;

void spit(const fs::path& p, const std::string& bytes) { std::ofstream(p, std::ios::binary) << bytes; }

core::CloudFields allFields() {
    core::CloudFields f;
    f.intensity = f.returns = f.incidence = f.scan_angle = f.height_above_ground = true;
    return f;
}

// Points on a 1 mm grid (LAS's resolution) near a georeferenced origin, every field set.
core::PointCloud ladarCloud(const glm::dvec3& origin, bool rgb = true) {
    core::PointCloud c;
    c.origin = origin;
    c.fields = allFields();
    c.fields.rgb = rgb;
    for (int i = 0; i < 300; ++i) {
        core::CloudPoint p;
        p.position = {float(i) * 0.125f - 17.0f, float(i % 17) * 1.5f, float(i % 5) * -0.25f};
        p.rgb = rgb ? core::packRgb(std::uint8_t(i), std::uint8_t(255 - i % 256), std::uint8_t(i * 7)) : core::kWhite;
        p.range_m = 100.0f + float(i) * 0.5f;
        p.incidence_deg = float(i % 90) + 0.25f;
        p.scan_angle_deg = float(i % 61) * 0.006f * 100.0f - 18.0f;  // multiples of 0.6 deg
        p.height_above_ground_m = float(i % 13) * 0.5f;
        p.intensity = std::uint16_t(i * 211);
        p.view = std::uint16_t(i % 7);
        p.label = Role(i % 3);
        p.return_number = std::uint8_t(1 + i % 3);
        p.returns = 3;
        c.points.push_back(p);
    }
    return c;
}

void checkSame(const core::PointCloud& a, const core::PointCloud& b, double tol_m) {
    REQUIRE(a.points.size() == b.points.size());
    for (std::size_t i = 0; i < a.points.size(); ++i) {
        const core::CloudPoint& p = a.points[i];
        const core::CloudPoint& q = b.points[i];
        const glm::dvec3 wp = a.origin + glm::dvec3(p.position), wq = b.origin + glm::dvec3(q.position);
        INFO("point " << i);
        CHECK(std::fabs(wp.x - wq.x) <= tol_m);
        CHECK(std::fabs(wp.y - wq.y) <= tol_m);
        CHECK(std::fabs(wp.z - wq.z) <= tol_m);
        if (a.fields.rgb && b.fields.rgb) CHECK(p.rgb == q.rgb);
        CHECK(p.label == q.label);
        CHECK(p.view == q.view);
        CHECK(p.range_m == q.range_m);
        CHECK(p.intensity == q.intensity);
        CHECK(p.return_number == q.return_number);
        CHECK(p.returns == q.returns);
        CHECK(p.incidence_deg == q.incidence_deg);
        CHECK(std::fabs(p.scan_angle_deg - q.scan_angle_deg) <= 0.003f);
        CHECK(p.height_above_ground_m == q.height_above_ground_m);
    }
}

}  // namespace

TEST_CASE("las_io: every optional field round-trips through PCD, PLY, LAS and LAZ") {
    TempDir dir("ladar_fields");
    const core::PointCloud c = ladarCloud({1000.0, 2000.0, 30.0});
    const std::pair<CloudFormat, const char*> formats[] = {
        {CloudFormat::PcdBinary, "a.pcd"}, {CloudFormat::PcdAscii, "b.pcd"}, {CloudFormat::PlyBinary, "c.ply"},
        {CloudFormat::PlyAscii, "d.ply"},  {CloudFormat::Las, "e.las"},      {CloudFormat::Laz, "f.laz"}};
    for (const auto& [format, name] : formats) {
        INFO(name);
        io::writeCloud(dir.path / name, c, format);
        const core::PointCloud r = io::readCloud(dir.path / name);
        CHECK(r.fields.intensity);
        CHECK(r.fields.returns);
        CHECK(r.fields.incidence);
        CHECK(r.fields.scan_angle);
        CHECK(r.fields.height_above_ground);
        const bool las = format == CloudFormat::Las || format == CloudFormat::Laz;
        // PCD/PLY keep the exact floats; LAS keeps 1 mm.
        checkSame(c, r, las ? 0.0005 : 0.0);
        if (!las) CHECK(r.origin == c.origin);
    }
    // The default fields leave the new ones out of the file (the generator's output).
    core::PointCloud plain = c;
    plain.fields = core::CloudFields{};
    io::writeCloud(dir.path / "plain.pcd", plain, CloudFormat::PcdBinary);
    CHECK(slurp(dir.path / "plain.pcd").find("\nFIELDS x y z rgb label view range\n") != std::string::npos);
    CHECK_FALSE(io::readCloud(dir.path / "plain.pcd").fields.intensity);
}

TEST_CASE("las_io: LAS header, classes, GPS time, point source and point format") {
    TempDir dir("las_header");
    const core::PointCloud c = ladarCloud({5400000.25, -3000000.5, 120.0});
    io::LasOptions las;
    las.class_of_role[int(Role::Target)] = 77;
    las.class_of_role[int(Role::Environment)] = 6;
    las.gps_start_s = 1000.0;
    las.view_interval_s = 0.5;
    io::writeCloud(dir.path / "a.las", c, CloudFormat::Las, las);
    const std::string bytes = slurp(dir.path / "a.las");
    REQUIRE(bytes.size() > 375);
    CHECK(bytes.substr(0, 4) == "LASF");
    CHECK(int(bytes[24]) == 1);
    CHECK(int(bytes[25]) == 4);
    CHECK(int(std::uint8_t(bytes[104])) == 7);
    double scale = 0, offset = 0;
    std::memcpy(&scale, bytes.data() + 131, 8);
    std::memcpy(&offset, bytes.data() + 155, 8);
    CHECK(scale == 0.001);
    CHECK(offset == 5400000.25);
    std::uint64_t count = 0;
    std::memcpy(&count, bytes.data() + 247, 8);
    CHECK(count == c.points.size());
    // First record after the header and VLRs: classification (byte 16) and GPS time (22).
    std::uint32_t data_at = 0;
    std::memcpy(&data_at, bytes.data() + 96, 4);
    std::uint16_t record = 0;
    std::memcpy(&record, bytes.data() + 105, 2);
    CHECK(record == 36 + 4 + 1 + 4 + 4);  // format 7 + range, label, incidence, height
    for (std::size_t i : {0u, 1u, 2u, 10u}) {
        const char* rec = bytes.data() + data_at + i * record;
        const int expect = c.points[i].label == Role::Ground ? 2 : c.points[i].label == Role::Target ? 77 : 6;
        CHECK(int(std::uint8_t(rec[16])) == expect);
        double gps = 0;
        std::memcpy(&gps, rec + 22, 8);
        CHECK(gps == 1000.0 + 0.5 * c.points[i].view);
        std::uint16_t source = 0;
        std::memcpy(&source, rec + 20, 2);
        CHECK(source == c.points[i].view);
    }
    // Without colours (--white): point format 6.
    io::writeCloud(dir.path / "w.laz", ladarCloud({0, 0, 0}, false), CloudFormat::Laz);
    const std::string w = slurp(dir.path / "w.laz");
    CHECK((std::uint8_t(w[104]) & 0x3F) == 6);
    CHECK_FALSE(io::readCloud(dir.path / "w.laz").fields.rgb);
}

TEST_CASE("las_io: the LAS reader streams in chunks and maps ASPRS classes without our label") {
    TempDir dir("las_chunks");
    core::PointCloud c = ladarCloud({10000000.0, 10000000.0, 500.0});
    c.fields.label = false;  // classes only, as real drone data
    io::LasOptions las;
    las.class_of_role[int(Role::Environment)] = 45;  // not an ASPRS standard class
    io::writeCloud(dir.path / "a.laz", c, CloudFormat::Laz, las);
    io::CloudReader reader(dir.path / "a.laz");
    CHECK(reader.declaredPoints() == c.points.size());
    std::vector<core::CloudPoint> got;
    int chunks = 0;
    while (reader.nextChunk(got, 64)) ++chunks;
    CHECK(chunks == 5);
    REQUIRE(got.size() == c.points.size());
    for (std::size_t i = 0; i < got.size(); ++i) {
        // 2 -> ground, 64 -> target, unknown 45 -> environment.
        CHECK(got[i].label == c.points[i].label);
        const glm::dvec3 w = reader.origin() + glm::dvec3(got[i].position);
        CHECK(std::fabs(w.x - (c.origin.x + c.points[i].position.x)) <= 0.0005);
    }
    CHECK(reader.warning() == "las: " + (dir.path / "a.laz").string() +
                                  ": 100 points have an ASPRS class this reader does not know (the first: 45); "
                                  "read as environment");
}

TEST_CASE("las_io: doubles at 10^7 m keep their millimetres in PLY, PCD and LAS") {
    TempDir dir("georef_doubles");
    const double base[3] = {10000000.0, 5400000.0, 1234.5};
    std::string ply_body, pcd_body, text;
    for (int i = 0; i < 10; ++i) {
        const double xyz[3] = {base[0] + 0.001 * i + 0.123, base[1] - 0.007 * i, base[2] + 0.0005 * i};
        ply_body.append(reinterpret_cast<const char*>(xyz), 24);
        pcd_body.append(reinterpret_cast<const char*>(xyz), 24);
        char line[128];
        std::snprintf(line, sizeof line, "%.4f %.4f %.4f\n", xyz[0], xyz[1], xyz[2]);
        text += line;
    }
    spit(dir.path / "a.ply",
         "ply\nformat binary_little_endian 1.0\nelement vertex 10\nproperty double x\n"
         "property double y\nproperty double z\nend_header\n" +
             ply_body);
    spit(dir.path / "b.ply",
         "ply\nformat ascii 1.0\nelement vertex 10\nproperty double x\n"
         "property double y\nproperty double z\nend_header\n" +
             text);
    spit(dir.path / "c.pcd", "FIELDS x y z\nSIZE 8 8 8\nTYPE F F F\nWIDTH 10\nDATA binary\n" + pcd_body);
    spit(dir.path / "d.pcd", "FIELDS x y z\nSIZE 8 8 8\nTYPE F F F\nWIDTH 10\nDATA ascii\n" + text);
    for (const char* name : {"a.ply", "b.ply", "c.pcd", "d.pcd"}) {
        INFO(name);
        const core::PointCloud r = io::readCloud(dir.path / name);
        REQUIRE(r.points.size() == 10);
        for (int i = 0; i < 10; ++i) {
            const glm::dvec3 w = r.origin + glm::dvec3(r.points[std::size_t(i)].position);
            CHECK(std::fabs(w.x - (base[0] + 0.001 * i + 0.123)) <= 0.001);
            CHECK(std::fabs(w.y - (base[1] - 0.007 * i)) <= 0.001);
            CHECK(std::fabs(w.z - (base[2] + 0.0005 * i)) <= 0.001);
        }
    }
    // LAS at 10^7 m: written and read back within 1 mm.
    const core::PointCloud c = ladarCloud({base[0], base[1], base[2]});
    io::writeCloud(dir.path / "e.las", c, CloudFormat::Las);
    checkSame(c, io::readCloud(dir.path / "e.las"), 0.001);
}

TEST_CASE("las_io: ASPRS classes in a label field are roles, not a rejected file") {
    TempDir dir("asprs_labels");
    // Not our file (no ladarvr origin): 0..2 are our roles, 3 on ASPRS classes.
    spit(dir.path / "a.pcd",
         "FIELDS x y z label\nSIZE 4 4 4 1\nTYPE F F F U\nWIDTH 4\nDATA ascii\n"
         "0 0 0 6\n1 0 0 64\n2 0 0 1\n3 0 0 99\n");
    io::CloudReader a(dir.path / "a.pcd");
    std::vector<core::CloudPoint> pts;
    while (a.nextChunk(pts)) {}
    REQUIRE(pts.size() == 4);
    CHECK(pts[0].label == Role::Environment);  // 6 building
    CHECK(pts[1].label == Role::Target);       // 64, our target class
    CHECK(pts[2].label == Role::Environment);
    CHECK(pts[3].label == Role::Environment);  // unknown: one warning line
    CHECK(a.warning().find("1 points have an ASPRS class this reader does not know (the first: 99)") !=
          std::string::npos);
    // A field named classification holds ASPRS classes throughout: 2 is ground.
    spit(dir.path / "b.ply",
         "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
         "property float z\nproperty uchar classification\nend_header\n1 2 3 2\n4 5 6 6\n");
    const core::PointCloud b = io::readCloud(dir.path / "b.ply");
    CHECK(b.points[0].label == Role::Ground);
    CHECK(b.points[1].label == Role::Environment);
}

TEST_CASE("las_io: bad LAS files give one line and no crash") {
    TempDir dir("bad_las");
    io::writeCloud(dir.path / "good.las", ladarCloud({1, 2, 3}), CloudFormat::Las);
    io::writeCloud(dir.path / "good.laz", ladarCloud({1, 2, 3}), CloudFormat::Laz);
    const std::string las = slurp(dir.path / "good.las");
    const std::string laz = slurp(dir.path / "good.laz");
    const fs::path p = dir.path / "bad.las";
    const std::string pre = "las: " + p.string() + ": ";
    auto error = [&](const std::string& bytes) {
        spit(p, bytes);
        try {
            io::readCloud(p);
        } catch (const core::Error& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    CHECK(error(las.substr(0, 100)) == pre + "truncated: a LAS header needs 227 bytes, the file has 100");
    std::string v = las;
    v[25] = 9;
    CHECK(error(v) == pre + "LAS version 1.9 is not one of 1.0 to 1.4");
    v = las;
    v[104] = 12;
    CHECK(error(v) == pre + "point data format 12 is not one of 0 to 10");
    CHECK(error(las.substr(0, las.size() - 7)).rfind(pre + "truncated: the header says 300 points", 0) == 0);
    v = las;
    const std::uint32_t many = 1000000;
    std::memcpy(v.data() + 100, &many, 4);
    CHECK(error(v) == pre + "1000000 VLRs cannot fit before the point data");
    v = las;
    const double zero = 0.0;
    std::memcpy(v.data() + 139, &zero, 8);
    CHECK(error(v) == pre + "the scale and offset of y must be finite and the scale non-zero");
    // A LAZ cut short or with its compressed data overwritten: an error line, no crash.
    for (std::size_t cut : {laz.size() / 2, laz.size() - 20}) {
        const std::string e = error(laz.substr(0, cut));
        CHECK(e.rfind(pre, 0) == 0);
        CHECK(e.find('\n') == std::string::npos);
    }
}
