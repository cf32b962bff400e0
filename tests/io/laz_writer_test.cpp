// The LAZ writer compresses chunks on worker threads and joins them with a chunk table it
// codes itself: the file must be the one LASzip writes alone with the same chunk size,
// byte for byte (header counts and bounds, chunks, table), for any thread count and any
// way the points arrive; LASzip must seek through it; errors in a worker reach the caller.
#include <test_files.hpp>
#include <core/error.hpp>
#include <io/cloud_io.hpp>

#include "../../io/src/las/las_record.hpp"

#include <doctest/doctest.h>

#include <laszip/laszip_api.h>

#include <fcntl.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <random>
#include <string>

namespace fs = std::filesystem;

namespace {

using test_support::slurp;
using test_support::TempDir;

core::CloudFields ladarFields(bool rgb) {
    core::CloudFields f;
    f.rgb = rgb;
    f.intensity = f.returns = f.incidence = f.scan_angle = f.height_above_ground = true;
    return f;
}

// Points that compress unevenly (a smooth scan, then noise), so chunks differ in size.
std::vector<core::CloudPoint> scan(std::size_t n, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    std::vector<core::CloudPoint> pts(n);
    for (std::size_t i = 0; i < n; ++i) {
        core::CloudPoint& p = pts[i];
        const float t = float(i) * 0.01f;
        const bool noisy = (i / 30000) % 2 == 1;
        p.position = {std::cos(t) * 40.0f + (noisy ? u(rng) * 30.0f : 0.0f), std::sin(t * 0.5f) * 35.0f,
                      float(i % 97) * 0.02f + (noisy ? u(rng) : 0.0f)};
        p.rgb = core::packRgb(std::uint8_t(i), std::uint8_t(i >> 8), std::uint8_t(i * 13));
        p.range_m = 300.0f + p.position.x;
        p.incidence_deg = float(i % 90);
        p.scan_angle_deg = float(i % 50) * 0.06f - 1.5f;
        p.height_above_ground_m = p.position.z;
        p.intensity = std::uint16_t(i * 37);
        p.view = std::uint16_t(i / 4000);
        p.label = core::Role(i % 3);
        p.return_number = std::uint8_t(1 + i % 2);
        p.returns = 2;
    }
    return pts;
}

// The same points written by LASzip alone: its own chunking, chunk table and inventory.
// LASzip stamps its own name as the generating software when it opens a writer, so the
// field is put back to ours (the one header field LASzip's writer cannot be given).
std::string laszipAlone(const fs::path& path, const std::vector<core::CloudPoint>& pts, const glm::dvec3& origin,
                        const core::CloudFields& fields) {
    io::detail::LasRecord record("reference", origin, fields, io::LasOptions{});
    laszip_POINTER zip = nullptr;
    REQUIRE(laszip_create(&zip) == 0);
    record.setUp(zip);
    REQUIRE(laszip_set_chunk_size(zip, laszip_U32(io::lazChunkPoints())) == 0);
    laszip_point_struct* q = nullptr;
    REQUIRE(laszip_get_point_pointer(zip, &q) == 0);
    REQUIRE(laszip_open_writer(zip, path.c_str(), 1) == 0);
    for (std::size_t i = 0; i < pts.size(); ++i) {
        record.fill(*q, pts[i], i);
        REQUIRE(laszip_write_point(zip) == 0);
        REQUIRE(laszip_update_inventory(zip) == 0);
    }
    REQUIRE(laszip_close_writer(zip) == 0);
    laszip_destroy(zip);
    const int fd = ::open(path.c_str(), O_WRONLY | O_CLOEXEC);
    REQUIRE(fd >= 0);
    record.stampSoftware(fd);
    ::close(fd);
    return slurp(path);
}

std::string ours(const fs::path& path, const std::vector<core::CloudPoint>& pts, const glm::dvec3& origin,
                 const core::CloudFields& fields, int threads, std::size_t piece) {
    io::LasOptions o;
    o.threads = threads;
    io::CloudWriter w(path, io::CloudFormat::Laz, origin, fields, o);
    for (std::size_t i = 0; i < pts.size(); i += piece)
        w.append(std::span(pts).subspan(i, std::min(piece, pts.size() - i)));
    w.commit();
    return slurp(path);
}

// The offset of the first byte that differs (the shorter size when one is a prefix).
std::size_t firstDifference(const std::string& a, const std::string& b) {
    const std::size_t n = std::min(a.size(), b.size());
    for (std::size_t i = 0; i < n; ++i)
        if (a[i] != b[i]) return i;
    return a.size() == b.size() ? b.size() : n;
}

}  // namespace

TEST_CASE("laz_writer: chunks compressed in parallel make LASzip's own file, byte for byte") {
    TempDir dir("laz_writer");
    const glm::dvec3 origin(512345.678, 5412345.25, 301.5);
    const std::size_t chunk = io::lazChunkPoints();
    for (const std::size_t n : {std::size_t(0), std::size_t(1), chunk - 1, chunk, chunk + 1, 3 * chunk + 4321}) {
        for (const bool rgb : {true, false}) {
            CAPTURE(n);
            CAPTURE(rgb);
            const auto pts = scan(n, std::uint32_t(n));
            const core::CloudFields fields = ladarFields(rgb);
            const std::string reference = laszipAlone(dir.path / "reference.laz", pts, origin, fields);
            REQUIRE(reference.size() > 375);
            for (const int threads : {0, 1, 3}) {
                CAPTURE(threads);
                const std::size_t piece = threads == 1 ? 7777 : 65536;
                const std::string mine = ours(dir.path / "ours.laz", pts, origin, fields, threads, piece);
                CHECK(mine.size() == reference.size());
                CHECK(firstDifference(mine, reference) == reference.size());
            }
        }
    }
}

TEST_CASE("laz_writer: the header names ladarvr and its version, and the creation date") {
    TempDir dir("laz_header");
    const std::string mine = ours(dir.path / "h.laz", scan(10, 1), glm::dvec3(0.0), ladarFields(true), 1, 10);
    REQUIRE(mine.size() > 375);
    CHECK(std::string(mine.data() + 58) == "ladarvr " LADARVR_VERSION);
    const io::detail::LasDate date = io::detail::lasCreationDate();
    std::uint16_t day = 0, year = 0;
    std::memcpy(&day, mine.data() + 90, 2);
    std::memcpy(&year, mine.data() + 92, 2);
    CHECK(day == date.day);
    CHECK(year == date.year);
    CHECK(day >= 1);
    CHECK(day <= 366);
    CHECK(year >= 2024);
}

TEST_CASE("laz_writer: LASzip seeks by our chunk table and reads every point back") {
    TempDir dir("laz_seek");
    const glm::dvec3 origin(0.0, 0.0, 0.0);
    const std::size_t n = 4 * io::lazChunkPoints() + 77;
    const auto pts = scan(n, 7);
    const fs::path path = dir.path / "seek.laz";
    ours(path, pts, origin, ladarFields(true), 2, 100000);
    laszip_POINTER zip = nullptr;
    REQUIRE(laszip_create(&zip) == 0);
    laszip_BOOL compressed = 0;
    REQUIRE(laszip_open_reader(zip, path.c_str(), &compressed) == 0);
    CHECK(compressed == 1);
    laszip_header_struct* h = nullptr;
    REQUIRE(laszip_get_header_pointer(zip, &h) == 0);
    CHECK(h->extended_number_of_point_records == n);
    laszip_point_struct* q = nullptr;
    REQUIRE(laszip_get_point_pointer(zip, &q) == 0);
    // Backwards from the last chunk: every seek goes through the table.
    for (const std::size_t at : {n - 1, 3 * io::lazChunkPoints() + 5, std::size_t(123456), std::size_t(49999)}) {
        CAPTURE(at);
        REQUIRE(laszip_seek_point(zip, laszip_I64(at)) == 0);
        REQUIRE(laszip_read_point(zip) == 0);
        CHECK(q->X == laszip_I32(std::lround(double(pts[at].position.x) * 1000.0)));
        CHECK(q->Y == laszip_I32(std::lround(double(pts[at].position.y) * 1000.0)));
        CHECK(q->intensity == pts[at].intensity);
    }
    laszip_close_reader(zip);
    laszip_destroy(zip);
}

TEST_CASE("laz_writer: a bad point in a worker's chunk is the caller's error, and no file is left") {
    TempDir dir("laz_error");
    auto pts = scan(3 * io::lazChunkPoints(), 3);
    pts[120000].position.x = 3.0e6f;  // beyond LAS's reach at 1 mm from the origin
    const fs::path path = dir.path / "bad.laz";
    io::LasOptions o;
    o.threads = 2;
    try {
        io::CloudWriter w(path, io::CloudFormat::Laz, glm::dvec3(0.0), ladarFields(true), o);
        w.append(pts);
        w.commit();
        FAIL("no error");
    } catch (const core::Error& e) {
        CHECK(std::string(e.what()) ==
              "output: " + path.string() +
                  ": point 120000 lies beyond 2,147 km of the cloud origin, out of LAS's reach at 1 mm");
    }
    CHECK_FALSE(fs::exists(path));
    std::size_t left = 0;
    for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir.path)) ++left;
    CHECK(left == 0);
}

TEST_CASE("las_record: quantize rounds as std::round does, half away from zero, up to LAS's reach") {
    const io::detail::LasRecord record("output: q.laz", glm::dvec3(0.0), ladarFields(true), io::LasOptions{});
    const auto expected = [](float f) { return std::round(double(f) / io::detail::LasRecord::kScale_m); };
    std::vector<float> values = {0.0f, -0.0f, 0.0005f,   -0.0005f,   0.0015f,     -0.0025f,
                                 1.0f, -1.0f, 123.4565f, 2147483.5f, -2147483.5f, std::nextafter(2147483.75f, 0.0f)};
    // Halves exactly: a float k + 0.5 millimetres is a double k + 0.5 after the division
    // only sometimes, so take the floats whose quotient is a half.
    for (int k = -2000; k <= 2000; ++k) {
        const float f = float((k + 0.5) * 0.001);
        if (std::fabs(double(f) / io::detail::LasRecord::kScale_m - (k + 0.5)) == 0.0) values.push_back(f);
    }
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-2.1e6f, 2.1e6f), small(-3.0f, 3.0f);
    for (int i = 0; i < 200000; ++i) values.push_back(i % 2 ? u(rng) : small(rng));
    std::size_t halves = 0;
    for (float f : values) {
        const double v = double(f) / io::detail::LasRecord::kScale_m;
        if (std::fabs(v - std::trunc(v)) == 0.5) ++halves;
        core::CloudPoint p;
        p.position = glm::vec3(f, -f, f);
        const auto xyz = record.quantize(p, 0);
        CHECK(double(xyz[0]) == expected(f));
        CHECK(double(xyz[1]) == expected(-f));
    }
    CHECK(halves > 10);  // the ties were really tried
    // 2,147,483.6475 m rounds to 2^31 mm, one past the reach.
    for (float f : {2147483.75f, -2147483.75f, std::nanf(""), INFINITY}) {
        core::CloudPoint p;
        p.position.x = f;
        CHECK_THROWS_WITH_AS(
            record.quantize(p, 9),
            "output: q.laz: point 9 lies beyond 2,147 km of the cloud origin, out of LAS's reach at 1 mm", core::Error);
    }
}
