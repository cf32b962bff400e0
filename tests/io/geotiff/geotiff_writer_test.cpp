// Tests of io::geoKeysForWkt and io::writeGeoTiff: the keys of each kind of CRS (an EPSG
// code where the WKT has one, user-defined with its name where not, the vertical part of a
// compound CRS, none for an empty WKT, a problem for one PROJ cannot read); the file's
// layout read back tag by tag here, its Deflate strips inflated and the floating-point
// predictor undone, as a classic TIFF and as a BigTIFF, and which of the two a grid gets
// (geotiff.js reads both in tests/app/cmd_ground_geotiff_test.sh);
// one-line errors.
#include <doctest/doctest.h>

#include <core/error.hpp>
#include <io/geotiff.hpp>

#include "test_files.hpp"

#include <cmath>
#include <cstring>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <zlib.h>

namespace {

const char* const kUtm32 =
    "PROJCS[\"WGS 84 / UTM zone 32N\",GEOGCS[\"WGS 84\",DATUM[\"WGS_1984\",SPHEROID[\"WGS "
    "84\",6378137,298.257223563]],PRIMEM[\"Greenwich\",0],UNIT[\"degree\",0.0174532925199433]],"
    "PROJECTION[\"Transverse_Mercator\"],PARAMETER[\"latitude_of_origin\",0],PARAMETER[\"central_meridian\",9],"
    "PARAMETER[\"scale_factor\",0.9996],PARAMETER[\"false_easting\",500000],PARAMETER[\"false_northing\",0],"
    "UNIT[\"metre\",1,AUTHORITY[\"EPSG\",\"9001\"]],AUTHORITY[\"EPSG\",\"32632\"]]";

// A local Transverse Mercator no EPSG code names, in US survey feet.
const char* const kLocalFeet =
    "PROJCS[\"site grid\",GEOGCS[\"WGS 84\",DATUM[\"WGS_1984\",SPHEROID[\"WGS "
    "84\",6378137,298.257223563]],PRIMEM[\"Greenwich\",0],UNIT[\"degree\",0.0174532925199433]],"
    "PROJECTION[\"Transverse_Mercator\"],PARAMETER[\"latitude_of_origin\",48.123],PARAMETER[\"central_meridian\",9.321]"
    ","
    "PARAMETER[\"scale_factor\",1],PARAMETER[\"false_easting\",1000],PARAMETER[\"false_northing\",2000],"
    "UNIT[\"US survey foot\",0.304800609601219]]";

std::map<std::uint16_t, io::GeoKey> byId(const std::vector<io::GeoKey>& keys) {
    std::map<std::uint16_t, io::GeoKey> m;
    for (const io::GeoKey& k : keys) m[k.id] = k;
    return m;
}

template <class T>
T le(const std::string& b, std::size_t at) {
    T v;
    std::memcpy(&v, b.data() + at, sizeof v);
    return v;
}

struct FileCloser {
    void operator()(std::FILE* f) const { std::fclose(f); }
};

std::string written(const io::GeoTiffGrid& g, const std::vector<io::GeoKey>& keys,
                    const std::vector<std::vector<float>>& rows) {
    const std::unique_ptr<std::FILE, FileCloser> f(std::tmpfile());
    REQUIRE(f);
    io::writeGeoTiff(
        f.get(), g, keys, [&](int r, float* v) { std::memcpy(v, rows[std::size_t(r)].data(), rows[0].size() * 4); },
        "t.tif");
    std::string bytes(std::size_t(std::ftell(f.get())), '\0');
    std::rewind(f.get());
    REQUIRE(std::fread(bytes.data(), 1, bytes.size(), f.get()) == bytes.size());
    return bytes;
}

// The first IFD of a little-endian TIFF, classic or BigTIFF, read as a reader would: for
// each tag its type, count and where its value lies (in the entry when it fits, else at
// the offset the entry gives).
struct Ifd {
    struct Entry {
        std::uint16_t type = 0;
        std::uint64_t count = 0;
        std::size_t value_at = 0;
    };
    bool big = false;
    std::uint64_t at = 0;
    std::map<std::uint16_t, Entry> entries;

    explicit Ifd(const std::string& b) {
        REQUIRE(b.size() >= 16);
        REQUIRE(b.substr(0, 2) == "II");
        const std::uint16_t version = le<std::uint16_t>(b, 2);
        REQUIRE((version == 42 || version == 43));
        big = version == 43;
        if (big) {
            REQUIRE(le<std::uint16_t>(b, 4) == 8);  // the offsets' size
            REQUIRE(le<std::uint16_t>(b, 6) == 0);
        }
        at = big ? le<std::uint64_t>(b, 8) : le<std::uint32_t>(b, 4);
        REQUIRE(at % 2 == 0);
        const std::uint64_t n = big ? le<std::uint64_t>(b, at) : le<std::uint16_t>(b, at);
        const std::size_t entry_bytes = big ? 20 : 12, first = at + (big ? 8 : 2), inline_bytes = big ? 8 : 4;
        REQUIRE(first + n * entry_bytes + inline_bytes <= b.size());
        std::uint16_t previous = 0;
        for (std::uint64_t i = 0; i < n; ++i) {
            const std::size_t e = first + i * entry_bytes;
            const std::uint16_t tag = le<std::uint16_t>(b, e);
            CHECK(tag > previous);  // TIFF wants them in order
            previous = tag;
            Entry entry;
            entry.type = le<std::uint16_t>(b, e + 2);
            entry.count = big ? le<std::uint64_t>(b, e + 4) : le<std::uint32_t>(b, e + 4);
            const std::size_t value = e + (big ? 12 : 8);
            const std::size_t size = entry.count * std::size_t(sizeOf(entry.type));
            entry.value_at = size <= inline_bytes
                                 ? value
                                 : std::size_t(big ? le<std::uint64_t>(b, value) : le<std::uint32_t>(b, value));
            REQUIRE(entry.value_at + size <= b.size());
            entries[tag] = entry;
        }
        // No next IFD.
        CHECK((big ? le<std::uint64_t>(b, first + n * 20) : le<std::uint32_t>(b, first + n * 12)) == 0);
    }
    static int sizeOf(std::uint16_t type) {
        switch (type) {
            case 2: return 1;   // ASCII
            case 3: return 2;   // SHORT
            case 4: return 4;   // LONG
            case 12: return 8;  // DOUBLE
            case 16: return 8;  // LONG8
            default: FAIL("a tag of type " << type); return 0;
        }
    }
    // Element k of an integer tag (SHORT, LONG or LONG8).
    std::uint64_t value(const std::string& b, std::uint16_t tag, std::size_t k = 0) const {
        const Entry& e = entries.at(tag);
        REQUIRE(k < e.count);
        const std::size_t at_k = e.value_at + k * std::size_t(sizeOf(e.type));
        switch (e.type) {
            case 3: return le<std::uint16_t>(b, at_k);
            case 4: return le<std::uint32_t>(b, at_k);
            case 16: return le<std::uint64_t>(b, at_k);
            default: FAIL("tag " << tag << " is not an integer"); return 0;
        }
    }
};

}  // namespace

TEST_CASE("geotiff: keys of a projected CRS with its EPSG code") {
    std::string problem;
    const auto keys = io::geoKeysForWkt(kUtm32, problem);
    CHECK(problem.empty());
    const auto k = byId(keys);
    CHECK(k.at(1024).value == 1);  // projected
    CHECK(k.at(1025).value == 1);  // pixel is area
    CHECK(k.at(3072).value == 32632);
    CHECK(k.at(3076).value == 9001);
    CHECK(k.count(1026) == 0);  // no citation where a code says it
    for (std::size_t i = 1; i < keys.size(); ++i) CHECK(keys[i - 1].id < keys[i].id);
}

TEST_CASE("geotiff: a CRS without a code is user-defined, named, in its unit") {
    std::string problem;
    const auto k = byId(io::geoKeysForWkt(kLocalFeet, problem));
    CHECK(problem.empty());
    CHECK(k.at(1024).value == 1);
    CHECK(k.at(3072).value == 32767);
    CHECK(k.at(1026).text == "site grid");
    CHECK(k.at(3076).value == 9003);  // US survey foot, from its length
}

TEST_CASE("geotiff: a geographic CRS and a compound CRS's vertical part") {
    std::string problem;
    const std::string geographic =
        "GEOGCS[\"WGS 84\",DATUM[\"WGS_1984\",SPHEROID[\"WGS 84\",6378137,298.257223563]],PRIMEM[\"Greenwich\",0],"
        "UNIT[\"degree\",0.0174532925199433,AUTHORITY[\"EPSG\",\"9122\"]],AUTHORITY[\"EPSG\",\"4326\"]]";
    const auto g = byId(io::geoKeysForWkt(geographic, problem));
    CHECK(problem.empty());
    CHECK(g.at(1024).value == 2);
    CHECK(g.at(2048).value == 4326);
    CHECK(g.at(2054).value == 9122);
    CHECK(g.count(3072) == 0);

    const std::string compound = std::string("COMPD_CS[\"UTM 32N + EGM96 height\",") + kUtm32 +
                                 ",VERT_CS[\"EGM96 height\",VERT_DATUM[\"EGM96 geoid\",2005],UNIT[\"metre\",1],"
                                 "AUTHORITY[\"EPSG\",\"5773\"]]]";
    const auto c = byId(io::geoKeysForWkt(compound, problem));
    CHECK(problem.empty());
    CHECK(c.at(3072).value == 32632);
    CHECK(c.at(4096).value == 5773);
    CHECK(c.at(4099).value == 9001);
}

TEST_CASE("geotiff: no keys for no CRS, a problem for a WKT PROJ cannot read") {
    std::string problem = "stale";
    CHECK(io::geoKeysForWkt("", problem).empty());
    CHECK(problem.empty());
    CHECK(io::geoKeysForWkt(std::string("\0\0", 2), problem).empty());
    CHECK(problem.empty());
    CHECK(io::geoKeysForWkt("PROJCS[\"broken\"", problem).empty());
    CHECK(problem == "PROJ cannot read the CRS's WKT");
}

TEST_CASE("geotiff: the file holds the rows as given, NaN as nodata, placed by its corner") {
    for (const io::TiffKind kind : {io::TiffKind::automatic, io::TiffKind::big}) {
        CAPTURE(int(kind));
        io::GeoTiffGrid g;
        g.columns = 3;
        g.rows = 2;
        g.west = 500000.5;
        g.north = 4000002.0;
        g.cell = 0.5;
        g.kind = kind;
        std::string problem;
        const std::vector<io::GeoKey> keys = io::geoKeysForWkt(kLocalFeet, problem);
        const std::vector<std::vector<float>> rows = {{1.5f, std::nanf(""), -2.25f}, {100.125f, 0.0f, 7.0f}};
        const std::string b = written(g, keys, rows);
        CHECK(b.size() == io::geoTiffBytes(g, keys));
        const Ifd ifd(b);
        // A grid this small is a classic TIFF unless a BigTIFF is asked for.
        CHECK(ifd.big == (kind == io::TiffKind::big));
        CHECK(io::geoTiffIsBig(g, keys) == ifd.big);
        CHECK(ifd.value(b, 256) == 3);
        CHECK(ifd.value(b, 257) == 2);
        CHECK(ifd.value(b, 258) == 32);
        CHECK(ifd.value(b, 339) == 3);
        CHECK(ifd.entries.at(273).type == (ifd.big ? 16 : 4));  // LONG8 offsets in a BigTIFF
        const std::size_t tie = ifd.entries.at(33922).value_at;
        CHECK(le<double>(b, tie + 24) == g.west);
        CHECK(le<double>(b, tie + 32) == g.north);
        CHECK(le<double>(b, ifd.entries.at(33550).value_at) == g.cell);
        CHECK(b.substr(ifd.entries.at(42113).value_at, 6) == std::string("-9999\0", 6));
        REQUIRE(ifd.entries.at(273).count == 2);
        for (int r = 0; r < 2; ++r) {
            const std::uint64_t strip = ifd.value(b, 273, std::size_t(r));
            CHECK(strip % 4 == 0);
            CHECK(ifd.value(b, 279, std::size_t(r)) == 12);
            for (int i = 0; i < 3; ++i) {
                const float want = std::isnan(rows[std::size_t(r)][std::size_t(i)])
                                       ? io::kGeoTiffNoData
                                       : rows[std::size_t(r)][std::size_t(i)];
                CHECK(le<float>(b, strip + 4 * std::size_t(i)) == want);
            }
        }
        // The citation through GeoAsciiParams, '|'-ended.
        CHECK(b.substr(ifd.entries.at(34737).value_at, 10) == "site grid|");
    }
}

TEST_CASE("geotiff: Deflate strips of up to 64 KiB with the floating-point predictor hold the rows as given") {
    for (const io::TiffKind kind : {io::TiffKind::automatic, io::TiffKind::big}) {
        CAPTURE(int(kind));
        io::GeoTiffGrid g;
        g.columns = 3000;  // 12,000 bytes a row: 5 rows a strip
        g.rows = 12;
        g.west = 1000.0;
        g.north = 2000.0;
        g.cell = 2.0;
        g.deflate = true;
        g.kind = kind;
        std::vector<std::vector<float>> rows(std::size_t(g.rows), std::vector<float>(std::size_t(g.columns)));
        for (std::size_t r = 0; r < rows.size(); ++r)
            for (std::size_t i = 0; i < rows[r].size(); ++i)
                rows[r][i] = (i + r) % 97 == 0 ? std::nanf("") : 250.0f + 0.01f * float(i) - 0.5f * float(r);
        std::string problem;
        const std::vector<io::GeoKey> keys = io::geoKeysForWkt(kUtm32, problem);
        const std::string b = written(g, keys, rows);
        CHECK(b.size() <= io::geoTiffBytes(g, keys));
        CHECK(b.size() < std::size_t(g.columns * g.rows * 4) / 2);  // smooth heights compress
        const Ifd ifd(b);
        CHECK(ifd.big == (kind == io::TiffKind::big));
        CHECK(ifd.value(b, 259) == 8);  // Deflate
        CHECK(ifd.value(b, 317) == 3);  // floating-point predictor
        CHECK(ifd.value(b, 278) == 5);  // rows a strip
        REQUIRE(ifd.entries.at(273).count == 3);
        REQUIRE(ifd.entries.at(279).count == 3);
        CHECK(ifd.entries.at(279).type == (ifd.big ? 16 : 4));
        const std::size_t width = std::size_t(g.columns);
        for (std::size_t k = 0; k < 3; ++k) {
            const std::uint64_t at = ifd.value(b, 273, k), size = ifd.value(b, 279, k);
            REQUIRE(at + size <= ifd.at);  // the strips come before the IFD
            const std::size_t strip_rows = std::min<std::size_t>(5, rows.size() - 5 * k);
            std::vector<unsigned char> raw(strip_rows * width * 4);
            uLongf raw_size = uLongf(raw.size());
            REQUIRE(uncompress(raw.data(), &raw_size, reinterpret_cast<const Bytef*>(b.data() + at), uLong(size)) ==
                    Z_OK);
            REQUIRE(raw_size == raw.size());
            for (std::size_t r = 0; r < strip_rows; ++r) {
                unsigned char* row = raw.data() + r * width * 4;
                for (std::size_t j = 1; j < width * 4; ++j) row[j] = (unsigned char)(row[j] + row[j - 1]);
                for (std::size_t i = 0; i < width; ++i) {
                    std::uint32_t bits = 0;
                    for (std::size_t p = 0; p < 4; ++p) bits |= std::uint32_t(row[p * width + i]) << (8 * (3 - p));
                    float v;
                    std::memcpy(&v, &bits, sizeof v);
                    const float given = rows[5 * k + r][i];
                    CHECK(v == (std::isnan(given) ? io::kGeoTiffNoData : given));
                }
            }
        }
    }
}

TEST_CASE("geotiff: a grid a classic TIFF might not hold is a BigTIFF unless classic is asked for") {
    io::GeoTiffGrid g;
    g.columns = 65536;  // 256 KiB a row: 16,384 rows uncompressed take 4 GiB, one byte past classic TIFF's offsets
    g.rows = 16383;
    g.cell = 1.0;
    CHECK_FALSE(io::geoTiffIsBig(g, {}));
    CHECK(io::geoTiffBytes(g, {}) <= 0xffffffffu);
    g.rows = 16384;
    CHECK(io::geoTiffIsBig(g, {}));
    const std::uint64_t big_bytes = io::geoTiffBytes(g, {});
    g.kind = io::TiffKind::classic;
    CHECK_FALSE(io::geoTiffIsBig(g, {}));
    const std::uint64_t classic_bytes = io::geoTiffBytes(g, {});
    CHECK(classic_bytes > 0xffffffffu);
    CHECK(big_bytes > classic_bytes);  // 8-byte offsets
    // With Deflate, on zlib's bound: a grid that compressed would surely fit still goes big.
    g.kind = io::TiffKind::automatic;
    g.deflate = true;
    g.rows = 16300;
    CHECK_FALSE(io::geoTiffIsBig(g, {}));
    g.rows = 16384;
    CHECK(io::geoTiffIsBig(g, {}));
    g.kind = io::TiffKind::big;
    g.rows = 1;
    CHECK(io::geoTiffIsBig(g, {}));
}

TEST_CASE("geotiff: bad grids give one line naming the output") {
    io::GeoTiffGrid g;
    g.columns = 0;
    g.rows = 2;
    g.cell = 1.0;
    const std::unique_ptr<std::FILE, FileCloser> f(std::tmpfile());
    const auto none = [](int, float*) {};
    CHECK(test_support::errorOf([&] { io::writeGeoTiff(f.get(), g, {}, none, "d.tif"); }) ==
          "output: d.tif: a grid of 0 x 2 cells; allowed at least 1 x 1");
    g.columns = 2;
    g.cell = std::nan("");
    CHECK(test_support::errorOf([&] { io::writeGeoTiff(f.get(), g, {}, none, "d.tif"); }) ==
          "output: d.tif: the grid's corner and cell must be finite, the cell > 0");
    g.cell = 1.0;
    g.columns = 70000;
    g.rows = 70000;
    g.kind = io::TiffKind::classic;
    const std::string error = test_support::errorOf([&] { io::writeGeoTiff(f.get(), g, {}, none, "d.tif"); });
    CHECK(error.starts_with("output: d.tif: a grid of 70000 x 70000 cells takes "));
    CHECK(error.ends_with(" bytes; a classic TIFF holds at most 4 GiB: write it as a BigTIFF instead"));
    CHECK(std::ftell(f.get()) == 0);  // refused before a byte is written
}
