// tests/io/las_crs_test.cpp: the CRS of WKT and GeoTIFF records (io/src/las/las_crs.cpp):
// names, EPSG codes and units of WKT 1 (projected, geographic, compound), WKT 2 and the
// GeoTIFF keys as real files hold them (4_6_crop.las's keys, byte for byte), and records
// that hold no CRS or are malformed, each said in `problem`, never a throw.
#include <core/random.hpp>
#include <io/las_crs.hpp>

#include "../../io/src/las/crs_wkt.hpp"

#include <doctest/doctest.h>

#include <cstdint>
#include <cstring>
#include <algorithm>
#include <string>
#include <vector>

namespace {

std::string shorts(const std::vector<std::uint16_t>& v) {
    std::string b(v.size() * 2, '\0');
    std::memcpy(b.data(), v.data(), b.size());
    return b;
}

std::string doubles(const std::vector<double>& v) {
    std::string b(v.size() * 8, '\0');
    std::memcpy(b.data(), v.data(), b.size());
    return b;
}

const char* kUtm42n =
    "PROJCS[\"WGS 84 / UTM zone 42N\",GEOGCS[\"WGS 84\",DATUM[\"WGS_1984\",SPHEROID[\"WGS 84\",6378137,"
    "298.257223563,AUTHORITY[\"EPSG\",\"7030\"]],AUTHORITY[\"EPSG\",\"6326\"]],PRIMEM[\"Greenwich\",0,"
    "AUTHORITY[\"EPSG\",\"8901\"]],UNIT[\"degree\",0.0174532925199433,AUTHORITY[\"EPSG\",\"9122\"]],"
    "AUTHORITY[\"EPSG\",\"4326\"]],PROJECTION[\"Transverse_Mercator\"],PARAMETER[\"latitude_of_origin\",0],"
    "PARAMETER[\"central_meridian\",69],PARAMETER[\"scale_factor\",0.9996],PARAMETER[\"false_easting\",500000],"
    "PARAMETER[\"false_northing\",0],UNIT[\"metre\",1,AUTHORITY[\"EPSG\",\"9001\"]],AXIS[\"Easting\",EAST],"
    "AXIS[\"Northing\",NORTH],AUTHORITY[\"EPSG\",\"32642\"]]";

}  // namespace

TEST_CASE("las_crs: WKT 1 projected: the root's name and AUTHORITY, its own UNIT (not the GEOGCS's degree)") {
    const io::LasCrs c = io::crsFromWkt(std::string(kUtm42n) + std::string(1, '\0') + "junk after the NUL");
    CHECK(c.problem == "");
    CHECK(c.source == "wkt");
    CHECK(c.kind == "projected");
    CHECK(c.name == "WGS 84 / UTM zone 42N");
    CHECK(c.epsg == 32642);
    CHECK(c.horizontal_unit.name == "metre");
    CHECK(c.horizontal_unit.epsg == 9001);
    CHECK(c.horizontal_unit.metres == 1.0);
    CHECK_FALSE(c.vertical_unit.stated());
}

TEST_CASE("las_crs: a compound WKT: the horizontal part's units and code, the VERT_CS's units") {
    const std::string wkt =
        "COMPD_CS[\"NAD83(HARN) / Oregon North (ft) + NAVD88 height (ftUS)\","
        "PROJCS[\"NAD83(HARN) / Oregon North (ft)\",GEOGCS[\"NAD83(HARN)\",DATUM[\"x\",SPHEROID[\"GRS 1980\",6378137,"
        "298.257222101]],UNIT[\"degree\",0.0174532925199433]],PROJECTION[\"Lambert_Conformal_Conic_2SP\"],"
        "UNIT[\"foot\",0.3048,AUTHORITY[\"EPSG\",\"9002\"]],AUTHORITY[\"EPSG\",\"2913\"]],"
        "VERT_CS[\"NAVD88 height (ftUS)\",VERT_DATUM[\"North American Vertical Datum 1988\",2005],"
        "UNIT[\"US survey foot\",0.304800609601219],AXIS[\"Gravity-related height\",UP],AUTHORITY[\"EPSG\",\"6360\"]]]";
    const io::LasCrs c = io::crsFromWkt(wkt);
    CHECK(c.problem == "");
    CHECK(c.kind == "compound");
    CHECK(c.name == "NAD83(HARN) / Oregon North (ft) + NAVD88 height (ftUS)");
    CHECK(c.epsg == 2913);  // the compound has no code of its own: the horizontal part's
    CHECK(c.horizontal_unit.name == "foot");
    CHECK(c.horizontal_unit.metres == 0.3048);
    CHECK(c.vertical_name == "NAVD88 height (ftUS)");
    CHECK(c.vertical_epsg == 6360);
    // Named by its length (no AUTHORITY): the US survey foot, 1200/3937 m.
    CHECK(c.vertical_unit.name == "US survey foot");
    CHECK(c.vertical_unit.epsg == 9003);
}

TEST_CASE("las_crs: ESRI's unit names and WKT 2's ID and axis units") {
    // ESRI: no AUTHORITY anywhere, the unit known by its factor.
    const io::LasCrs esri = io::crsFromWkt(
        "PROJCS[\"NAD_1983_StatePlane_Mississippi_West_FIPS_2302_Feet\",GEOGCS[\"GCS_North_American_1983\","
        "DATUM[\"D_North_American_1983\",SPHEROID[\"GRS_1980\",6378137.0,298.257222101]],PRIMEM[\"Greenwich\",0.0],"
        "UNIT[\"Degree\",0.0174532925199433]],PROJECTION[\"Transverse_Mercator\"],"
        "UNIT[\"Foot_US\",0.3048006096012192]]");
    CHECK(esri.epsg == 0);
    CHECK(esri.horizontal_unit.name == "US survey foot");
    CHECK(esri.horizontal_unit.epsg == 9003);
    // WKT 2: PROJCRS, ID["EPSG",code], the length unit inside each AXIS, "" inside a name.
    const io::LasCrs wkt2 = io::crsFromWkt(
        "PROJCRS[\"ETRS89 / \"\"UTM\"\" 32N\",BASEGEOGCRS[\"ETRS89\",DATUM[\"European Terrestrial Reference System "
        "1989\",ELLIPSOID[\"GRS 1980\",6378137,298.257222101,LENGTHUNIT[\"metre\",1]]],ANGLEUNIT[\"degree\","
        "0.0174532925199433]],CONVERSION[\"UTM zone 32N\",METHOD[\"Transverse Mercator\",ID[\"EPSG\",9807]]],"
        "CS[Cartesian,2],AXIS[\"(E)\",east,ORDER[1],LENGTHUNIT[\"metre\",1]],AXIS[\"(N)\",north,ORDER[2],"
        "LENGTHUNIT[\"metre\",1]],ID[\"EPSG\",25832]]");
    CHECK(wkt2.problem == "");
    CHECK(wkt2.kind == "projected");
    CHECK(wkt2.name == "ETRS89 / \"UTM\" 32N");
    CHECK(wkt2.epsg == 25832);
    CHECK(wkt2.horizontal_unit.name == "metre");
    // Geographic: the unit is an angle.
    const io::LasCrs geo = io::crsFromWkt(
        "GEOGCS[\"WGS 84\",DATUM[\"WGS_1984\",SPHEROID[\"WGS 84\",6378137,298.257223563]],"
        "UNIT[\"degree\",0.0174532925199433,AUTHORITY[\"EPSG\",\"9122\"]],AUTHORITY[\"EPSG\",\"4326\"]]");
    CHECK(geo.kind == "geographic");
    CHECK(geo.epsg == 4326);
    CHECK(geo.horizontal_unit.angular);
    CHECK(geo.horizontal_unit.metres == 0.0);
}

TEST_CASE("las_crs: WKT records without a CRS say why") {
    CHECK(io::crsFromWkt("").problem == "the WKT record is empty");
    CHECK(io::crsFromWkt(std::string(3, '\0')).problem == "the WKT record is empty");
    CHECK(io::crsFromWkt("''").problem == "the WKT record holds no CRS (its text: '')");
    CHECK(io::crsFromWkt("PROJCS[\"x\",UNIT[\"metre\",1]").problem ==
          "the WKT record cannot be read: PROJCS is not closed (at byte 26)");
    CHECK(io::crsFromWkt("PROJCS[\"x\" UNIT[\"metre\",1]]").problem ==
          "the WKT record cannot be read: ',' or ']' is expected in PROJCS (at byte 11)");
    CHECK(io::crsFromWkt("PROJCS[\"never closed]").problem ==
          "the WKT record cannot be read: a quoted name is not closed (at byte 21)");
    CHECK(io::crsFromWkt("TOWGS84[1,2,3]").problem == "the WKT record's TOWGS84 is not a CRS");
    // Nesting deeper than the parser's bound: refused, not a stack overflow.
    std::string deep;
    for (int i = 0; i < 100000; ++i) deep += "A[";
    CHECK(io::crsFromWkt(deep).problem == "the WKT record cannot be read: nodes nested deeper than 32 (at byte 64)");
    const io::LasCrs none = io::crsFromWkt("''");
    CHECK(none.source == "");
    CHECK(none.epsg == 0);
}

TEST_CASE("las_crs: GeoTIFF keys of 4_6_crop.las: EPSG:2903 in US survey feet, vertical too") {
    // The key directory and ASCII params of tests/data/real/4_6_crop.las (PDAL 2.7.1).
    const std::string dir =
        shorts({1,    1,     0,  11,   1024, 0,     1, 1,    1025, 0, 1, 1,    1026, 34737, 8, 0,
                2049, 34737, 12, 8,    2054, 0,     1, 9102, 3072, 0, 1, 2903, 3076, 0,     1, 9003,
                4096, 0,     1,  5103, 4097, 34737, 8, 20,   4098, 0, 1, 5703, 4099, 0,     1, 9003});
    const std::string ascii("unknown|NAD83(HARN)|unknown|\0", 29);
    const io::LasCrs c = io::crsFromGeoKeys(dir, "", ascii);
    CHECK(c.problem == "");
    CHECK(c.source == "geotiff");
    CHECK(c.kind == "projected");
    CHECK(c.epsg == 2903);
    CHECK(c.name == "");  // the citation "unknown" names nothing
    CHECK(c.horizontal_unit.name == "US survey foot");
    CHECK(c.horizontal_unit.epsg == 9003);
    CHECK(c.horizontal_unit.metres == doctest::Approx(0.3048006096012192).epsilon(1e-15));
    CHECK(c.vertical_epsg == 5103);
    CHECK(c.vertical_unit.name == "US survey foot");
}

TEST_CASE("las_crs: GeoTIFF citations, user-defined units from the doubles, geographic defaults") {
    // A projected CRS with its citation, its unit user-defined (32767) with its size in
    // the doubles (ProjLinearUnitSizeGeoKey), metres vertically.
    const std::string dir =
        shorts({1, 1, 0, 5, 1024, 0, 1, 1, 3072, 0, 1, 32767, 3073, 34737, 9, 0, 3076, 0, 1, 32767, 3077, 34736, 1, 1});
    // The citation's count (9) runs one byte past the ASCII params: what is there is read.
    const io::LasCrs c = io::crsFromGeoKeys(dir, doubles({7.0, 0.5}), "My grid|");
    CHECK(c.epsg == 0);  // user-defined: no code
    CHECK(c.name == "My grid");
    CHECK(c.horizontal_unit.name == "user-defined");
    CHECK(c.horizontal_unit.metres == 0.5);
    // Geographic without an angular unit key: GeoTIFF's default, the degree.
    const io::LasCrs geo = io::crsFromGeoKeys(shorts({1, 1, 0, 2, 1024, 0, 1, 2, 2048, 0, 1, 4269}), "", "");
    CHECK(geo.kind == "geographic");
    CHECK(geo.epsg == 4269);
    CHECK(geo.horizontal_unit.name == "degree");
    CHECK(geo.horizontal_unit.angular);
    // A unit code outside the table keeps its code.
    CHECK(io::epsgUnit(9099).name == "EPSG unit 9099");
    CHECK(io::epsgUnit(9099).metres == 0.0);
}

TEST_CASE("las_crs: malformed GeoTIFF records say why, and indices outside the arrays are not followed") {
    CHECK(io::crsFromGeoKeys(shorts({1, 1, 0}), "", "").problem ==
          "the GeoTIFF key directory has 6 bytes; at least 8 needed");
    CHECK(io::crsFromGeoKeys(shorts({2, 1, 0, 0}), "", "").problem ==
          "the GeoTIFF key directory's version is 2; allowed: 1");
    CHECK(io::crsFromGeoKeys(shorts({1, 1, 0, 3, 1024, 0, 1, 1}), "", "").problem ==
          "the GeoTIFF key directory lists 3 keys but holds room for 1");
    CHECK(io::crsFromGeoKeys(shorts({1, 1, 0, 0}), "", "").problem ==
          "the GeoTIFF keys name no CRS (no model type, projected or geographic CRS)");
    // A citation past the end of the ASCII params and a size past the doubles: ignored.
    const std::string dir =
        shorts({1, 1, 0, 4, 3072, 0, 1, 32632, 3073, 34737, 60000, 5, 3076, 0, 1, 32767, 3077, 34736, 1, 9000});
    const io::LasCrs c = io::crsFromGeoKeys(dir, doubles({1.0}), "short|");
    CHECK(c.problem == "");
    CHECK(c.epsg == 32632);
    CHECK(c.name == "");
    CHECK_FALSE(c.horizontal_unit.stated());
}

TEST_CASE("las_crs: mutated WKT and GeoTIFF records: a result or a one-line problem, never a throw") {
    // Seeded mutations of real records (bytes replaced by WKT's punctuation or any byte,
    // the record cut short), as a fuzzer would try them; under the sanitizer preset a read
    // out of bounds fails here.
    const std::string wkt = kUtm42n;
    const std::string dir =
        shorts({1, 1, 0, 4, 1024, 0, 1, 1, 3072, 0, 1, 32642, 3073, 34737, 22, 0, 3076, 0, 1, 9001});
    const std::string ascii = "WGS 84 / UTM zone 42N|WGS 84|";
    core::SplitMix64 rng(20240601);
    const char kPunctuation[] = "[](),\"\0 AZ";
    for (int round = 0; round < 3000; ++round) {
        std::string w = wkt, d = dir, a = ascii;
        for (int k = 0; k < 1 + round % 6; ++k) {
            const std::uint64_t r = rng.next();
            w[r % w.size()] = r & 1u ? kPunctuation[(r >> 8) % (sizeof kPunctuation - 1)] : char(r >> 16);
            d[(r >> 24) % d.size()] = char(r >> 32);
            a[(r >> 40) % a.size()] = char(r >> 48);
        }
        if (round % 5 == 0) w.resize(rng.next() % w.size());
        if (round % 7 == 0) d.resize(rng.next() % d.size());
        for (const io::LasCrs& c : {io::crsFromWkt(w), io::crsFromGeoKeys(d, doubles({0.5}), a)}) {
            CHECK(c.problem.find('\n') == std::string::npos);
            CHECK(c.source.empty() != c.problem.empty());  // a CRS, or why there is none
            CHECK(std::none_of(c.problem.begin(), c.problem.end(),
                               [](char ch) { return static_cast<unsigned char>(ch) < 0x20; }));
        }
    }
}

TEST_CASE("las_crs: the WKT made of GeoTIFF keys is one line whatever the vertical citation holds") {
    // EPSG:2903 in US survey feet, its heights in feet under a citation with a newline,
    // a quote, a control byte and bytes past ASCII (found by fuzz_las_crs): the name is
    // kept printable, and the WKT reads back as a CRS.
    const std::string dir = shorts({1, 1, 0, 4, 1024, 0, 1, 1, 3072, 0, 1, 2903, 4097, 34737, 20, 0, 4099, 0, 1, 9003});
    const std::string citation = std::string("NAVD88\n\"feet\"\x01\xff|", 17);
    const io::LasCrs keys = io::crsFromGeoKeys(dir, "", citation);
    REQUIRE(keys.source == "geotiff");
    REQUIRE(keys.vertical_unit.name == "US survey foot");
    std::string problem;
    const std::string wkt = io::detail::wktForCrs(keys, problem);
    REQUIRE(!wkt.empty());
    CHECK(problem.empty());
    CHECK(std::none_of(wkt.begin(), wkt.end(), [](char c) {
        return static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) >= 0x7f;
    }));
    CHECK(wkt.find("NAVD88feet") != std::string::npos);
    const io::LasCrs back = io::crsFromWkt(wkt);
    CHECK(back.source == "wkt");
    CHECK(back.vertical_unit.name == "US survey foot");
}

TEST_CASE("las_crs: a UNIT whose EPSG code names an angle has no length, whatever its factor") {
    // Found by fuzz_las_crs's contract: the degree's code under a factor of 1 gave an
    // angular unit of 1 m.
    const io::LasCrs c = io::crsFromWkt("PROJCS[\"x\",UNIT[\"metre\",1,AUTHORITY[\"EPSG\",\"9102\"]]]");
    REQUIRE(c.source == "wkt");
    CHECK(c.horizontal_unit.angular);
    CHECK(c.horizontal_unit.name == "degree");
    CHECK(c.horizontal_unit.metres == 0.0);
}
