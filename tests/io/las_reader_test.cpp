// Crafted LAS and LAZ files against the reader's checks (io/src/las/las_reader.cpp): each
// one is a real file from our writer with a few bytes changed where LASzip trusts the
// file (its VLR, the chunk table, the layer sizes of a chunk, the extra bytes VLRs), and
// each must give one line naming the field and what is allowed, never a crash. Also the
// trailing bytes of a header that counts too few points, and what a decoding failure says.
#include <test_files.hpp>
#include <test_paths.hpp>
#include <core/error.hpp>
#include <io/cloud_io.hpp>
#include <io/cloud_reader.hpp>

#include <doctest/doctest.h>
#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <string>

namespace fs = std::filesystem;
using io::CloudFormat;

namespace {

using test_support::errorOf;
using test_support::slurp;
using test_support::TempDir;

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

// A cloud of `n` points with our extra bytes (range, label), written as LAS or LAZ.
std::string written(CloudFormat format, int n = 400) {
    TempDir dir("las_reader_src");
    core::PointCloud c;
    c.origin = {5400000.0, 1000000.0, 0.0};
    c.fields.intensity = true;
    for (int i = 0; i < n; ++i) {
        core::CloudPoint p;
        p.position = {float(i % 37) * 0.5f, float(i / 37) * 0.25f, float(i % 5) * 0.125f};
        p.range_m = 100.0f + float(i);
        p.label = core::Role(i % 3);
        p.intensity = std::uint16_t(i * 97);
        c.points.push_back(p);
    }
    const fs::path path = dir.path / (format == CloudFormat::Laz ? "c.laz" : "c.las");
    io::writeCloud(path, c, format);
    return slurp(path);
}

// The error reading `bytes` (named .laz or .las), or "ok".
std::string readError(const std::string& bytes, const char* name = "x.laz") {
    const std::string e = errorOf([&] { io::readCloudData(bytes, name); });
    return e == "(no error)" ? "ok" : e;
}

void spit(const fs::path& p, const std::string& bytes) { std::ofstream(p, std::ios::binary) << bytes; }

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

// Where the VLR with `user` (and its payload) starts; npos when absent.
std::size_t vlrAt(const std::string& b, const std::string& user) {
    std::size_t at = get<std::uint16_t>(b, 94);
    for (std::uint32_t v = 0; v < get<std::uint32_t>(b, 100); ++v) {
        if (std::string(b.data() + at + 2, strnlen(b.data() + at + 2, 16)) == user) return at;
        at += 54 + get<std::uint16_t>(b, at + 20);
    }
    return std::string::npos;
}

std::size_t dataAt(const std::string& b) { return get<std::uint32_t>(b, 96); }
std::size_t tableAt(const std::string& b) { return std::size_t(get<std::int64_t>(b, dataAt(b))); }

}  // namespace

TEST_CASE("las_reader: our own LAS and LAZ read back (the files the crafted cases start from)") {
    CHECK(readError(written(CloudFormat::Laz)) == "ok");
    CHECK(readError(written(CloudFormat::Las), "x.las") == "ok");
    CHECK(readError(written(CloudFormat::Laz, 0)) == "ok");
    CHECK(readError(written(CloudFormat::Laz, 120000)) == "ok");  // three chunks
}

TEST_CASE("las_reader: a LASzip VLR whose compressor does not suit LAS 1.4 items is refused") {
    const std::string laz = written(CloudFormat::Laz);
    const std::size_t vlr = vlrAt(laz, "laszip encoded");
    REQUIRE(vlr != std::string::npos);
    REQUIRE(get<std::uint16_t>(laz, vlr + 54) == 3);
    for (const std::uint16_t compressor : {0, 1, 2, 4}) {
        CAPTURE(compressor);
        std::string b = laz;
        put<std::uint16_t>(b, vlr + 54, compressor);
        const std::string e = readError(b);
        CHECK(contains(e, "las: x.laz: the LASzip VLR is not one this reader knows (compressor " +
                              std::to_string(compressor) +
                              ", coder 0, 3 items in 52 bytes); allowed for point format 7: "
                              "compressor 3 (layered chunks), coder 0"));
    }
    // Items that are not the point format's: RGB and NIR where format 7 has RGB only, a
    // version of the older point-wise compressor.
    std::string b = laz;
    put<std::uint16_t>(b, vlr + 54 + 34 + 6, 12);  // the second item (RGB14) as RGBNIR14
    CHECK(contains(readError(b),
                   "the LASzip VLR's items (type/size/version: 10/30/v3, 12/6/v3, 14/5/v3) are not "
                   "those of point format 7 with 5 extra bytes"));
    b = laz;
    put<std::uint16_t>(b, vlr + 54 + 34 + 4, 1);  // POINT14 version 1
    CHECK(contains(readError(b), "are not those of point format 7"));
}

TEST_CASE("las_reader: a file cut inside the chunk table, or a table outside the file, is refused") {
    const std::string laz = written(CloudFormat::Laz);
    const std::size_t table = tableAt(laz);
    REQUIRE(table + 8 <= laz.size());
    for (const std::size_t cut : {table + 6, table + 7, table + 1, table}) {
        CAPTURE(cut - table);
        const std::string e = readError(laz.substr(0, cut));
        CHECK(contains(e, "las: x.laz: the chunk table's position " + std::to_string(table) +
                              " is outside the file; allowed: " + std::to_string(dataAt(laz) + 8) + " to " +
                              std::to_string(cut - 8) + " (the table needs 8 bytes)"));
    }
    std::string b = laz;
    put<std::int64_t>(b, dataAt(b), std::int64_t(1) << 40);
    CHECK(contains(readError(b), "the chunk table's position 1099511627776 is outside the file"));
    b = laz;
    put<std::uint32_t>(b, table, 7);
    CHECK(contains(readError(b), "the chunk table's version is 7; allowed: 0"));
}

TEST_CASE("las_reader: a chunk count with its high byte set is refused before LASzip allocates by it") {
    const std::string laz = written(CloudFormat::Laz);
    const std::size_t table = tableAt(laz);
    REQUIRE(get<std::uint32_t>(laz, table + 4) == 1);
    std::string b = laz;
    b[table + 7] = char(0x80);
    CHECK(contains(readError(b),
                   "las: x.laz: the chunk table lists 2147483649 chunks but the header's 400 points "
                   "fill 1 chunks of 50000 (the header counts fewer points than the data hold)"));
    b = laz;
    b[table + 7] = char(0xFF);
    CHECK(contains(readError(b), "the chunk table lists 4278190081 chunks"));
}

TEST_CASE("las_reader: layer sizes whose 32-bit sum wraps, or that pass the chunk's end, are refused") {
    const std::string laz = written(CloudFormat::Laz);
    const std::size_t record = get<std::uint16_t>(laz, 105);
    const std::size_t sizes = dataAt(laz) + 8 + record + 4;  // after the raw first point and the count
    REQUIRE(get<std::uint32_t>(laz, sizes - 4) == 400);
    std::string b = laz;
    put<std::uint32_t>(b, sizes, 0xFFFFFFFFu);  // channel, returns and XY
    put<std::uint32_t>(b, sizes + 4, 2u);       // Z: the sum wraps to 1 in LASzip's 32 bits
    CHECK(contains(readError(b), "las: x.laz: chunk 0's layers declare "));
    CHECK(contains(readError(b), " remain before byte " + std::to_string(tableAt(laz))));
    b = laz;
    put<std::uint32_t>(b, sizes - 4, 401);
    CHECK(contains(readError(b), "chunk 0 holds 401 points; allowed: 400 (of the header's 400)"));
}

TEST_CASE("las_reader: the header counting fewer points than the data hold is refused (LAS and LAZ)") {
    std::string las = written(CloudFormat::Las);
    const std::size_t record = get<std::uint16_t>(las, 105);
    put<std::uint64_t>(las, 247, 399);  // LAS 1.4's point count (the legacy one is 0 for format 6)
    CHECK(readError(las, "x.las") == "las: x.las: " + std::to_string(record) +
                                         " bytes follow the header's 399 points of " + std::to_string(record) +
                                         " bytes; allowed: the points end where the file, its waveform data or its "
                                         "EVLRs begin");
    // Bytes appended to a correct file, too.
    CHECK(contains(readError(written(CloudFormat::Las) + "junk", "x.las"), "4 bytes follow the header's 400 points"));
    std::string laz = written(CloudFormat::Laz);
    put<std::uint64_t>(laz, 247, 399);
    CHECK(contains(readError(laz), "chunk 0 holds 400 points; allowed: 399 (of the header's 399)"));
}

TEST_CASE("las_reader: two extra bytes VLRs (fields from one, sizes from the other) are refused") {
    const std::string las = written(CloudFormat::Las);
    const std::size_t vlr = vlrAt(las, "LASF_Spec");
    REQUIRE(vlr != std::string::npos);
    // A second extra bytes VLR describing one byte, put after the first: its fields say
    // one byte, the first one's range and label say five.
    std::string second = las.substr(vlr, 54 + 192);
    put<std::uint16_t>(second, 20, 192);
    second[54 + 2] = 1;  // unsigned char
    std::memcpy(second.data() + 54 + 4, "other\0\0", 7);
    std::string b = las.substr(0, dataAt(las)) + second + las.substr(dataAt(las));
    put<std::uint32_t>(b, 96, std::uint32_t(dataAt(las) + second.size()));
    put<std::uint32_t>(b, 100, get<std::uint32_t>(las, 100) + 1);
    CHECK(readError(b, "x.las") == "las: x.las: VLR " + std::to_string(get<std::uint32_t>(las, 100)) +
                                       " is a second extra bytes VLR; allowed: one per file");
}

TEST_CASE("las_reader: undecodable compressed points name the point and what is wrong with the file") {
    std::string laz = written(CloudFormat::Laz);
    const std::size_t record = get<std::uint16_t>(laz, 105);
    const std::size_t sizes = dataAt(laz) + 8 + record + 4;
    // The first layer (channel, returns and XY) empty: LASzip's decoder of it cannot start.
    const std::uint32_t first = get<std::uint32_t>(laz, sizes);
    put<std::uint32_t>(laz, sizes, 0u);
    put<std::uint32_t>(laz, sizes + 4, get<std::uint32_t>(laz, sizes + 4) + first);
    const std::string e = readError(laz);
    CHECK(e ==
          "las: x.laz: point 0 of 400: the compressed point data cannot be decoded; the LAZ file is corrupt or "
          "cut short");
}

TEST_CASE("las_reader: an empty or foreign file named .las is the LAS reader's to refuse, not PCD's") {
    TempDir dir("las_reader_empty");
    spit(dir.path / "empty.las", "");
    CHECK(errorOf([&] { io::readCloud(dir.path / "empty.las"); }) ==
          "las: " + (dir.path / "empty.las").string() + ": truncated: a LAS header needs 227 bytes, the file has 0");
    spit(dir.path / "text.laz", "# .PCD v0.7\nVERSION 0.7\n");
    CHECK(errorOf([&] { io::readCloud(dir.path / "text.laz"); }) ==
          "las: " + (dir.path / "text.laz").string() + ": not a LAS file: it starts with '# .P'; allowed: 'LASF'");
}

TEST_CASE("las_reader: EVLRs after the points are allowed, and must lie inside the file") {
    std::string las = written(CloudFormat::Las);
    const std::size_t end = las.size();
    // One EVLR after the points, of 4 bytes: read.
    std::string evlr(60, '\0');
    std::memcpy(evlr.data() + 2, "ladarvr", 7);
    put<std::uint64_t>(evlr, 20, 4);
    std::string b = las + evlr + "abcd";
    put<std::uint64_t>(b, 235, end);
    put<std::uint32_t>(b, 243, 1);
    CHECK(readError(b, "x.las") == "ok");
    put<std::uint64_t>(b, end + 20, std::uint64_t(1) << 50);
    CHECK(readError(b, "x.las") == "las: x.las: EVLR 0 at byte " + std::to_string(end) +
                                       " declares 1125899906842624 bytes "
                                       "but 4 follow it");
    put<std::uint32_t>(b, 243, 1000);
    CHECK(contains(readError(b, "x.las"), "1000 EVLRs from byte " + std::to_string(end) + " do not fit a file of"));
}

TEST_CASE("las_reader: LASzip aborting on corrupt compressed data ends only its decoding process") {
    // Valid header, VLRs, chunk table and layer sizes; corrupt arithmetic-coded points,
    // on which LASzip (built with assertions) aborts in ArithmeticDecoder::decodeSymbol.
    const fs::path kept =
        fs::path(test_support::dataDir()) / "io" / "fuzz_regressions" / "las_laszip_symbol_assert.laz";
    const std::string e = readError(slurp(kept));
    CHECK(e ==
          "las: x.laz: point 1 of 475: the compressed point data cannot be decoded; the LAZ file is corrupt "
          "(LASzip stopped by SIGABRT in the decoding process)");
    // The reader, and the process, go on: the same file twice, then a good one.
    CHECK(readError(slurp(kept)) == e);
    CHECK(readError(written(CloudFormat::Laz)) == "ok");
}

TEST_CASE("las reader: header bounds far from the points do not cost the coordinates their precision") {
    // Real files with their header's bounds zeroed (as some scripts write them): the frame
    // is placed on the first point, so every point's world coordinates are those of the
    // file as written, within a millimetre (from the zeroed bounds' frame, y near 3,689 km
    // would be rounded to 0.25 m). Bounds nearly right keep their own frame.
    TempDir dir("las_reader_bounds");
    const fs::path real = fs::path(test_support::dataDir()) / "real";
    for (const char* name : {"hexbin-crop.las", "FSite8_orig-utm.laz"}) {
        CAPTURE(name);
        std::string bytes = slurp(real / name);
        io::CloudReader original(real / name);
        const core::PointCloud want = io::readCloud(original);
        for (int k = 0; k < 6; ++k) put<double>(bytes, 179 + 8 * std::size_t(k), 0.0);
        const fs::path zeroed = dir.path / (std::string("zeroed_") + name);
        std::ofstream(zeroed, std::ios::binary) << bytes;
        io::CloudReader reader(zeroed);
        const core::PointCloud got = io::readCloud(reader);
        REQUIRE(got.points.size() == want.points.size());
        double worst = 0.0;
        for (std::size_t i = 0; i < got.points.size(); ++i) {
            const glm::dvec3 a = reader.origin() + glm::dvec3(got.points[i].position);
            const glm::dvec3 b = original.origin() + glm::dvec3(want.points[i].position);
            worst = std::max({worst, std::abs(a.x - b.x), std::abs(a.y - b.y), std::abs(a.z - b.z)});
        }
        CHECK(worst < 0.001);
        CHECK(glm::length(reader.origin()) > 1e5);  // on the survey, not at the zeroed bounds
    }
    // Bounds that miss the points by less than a kilometre keep the frame they give.
    std::string bytes = slurp(real / "hexbin-crop.las");
    const double max_x = get<double>(bytes, 179);
    put<double>(bytes, 179, max_x - 100.0);
    const fs::path shrunk = dir.path / "shrunk.las";
    std::ofstream(shrunk, std::ios::binary) << bytes;
    io::CloudReader original(real / "hexbin-crop.las");
    io::CloudReader reader(shrunk);
    CHECK(reader.origin().x == doctest::Approx(original.origin().x - 50.0).epsilon(1e-9));
}
