// fuzz/fuzz_las_crs.cpp: libFuzzer target for the CRS a LAS file's records declare
// (io/las_crs.hpp, io/src/las/las_crs.cpp): io::crsFromWkt on an OGC WKT record's payload,
// and io::crsFromGeoKeys on GeoTIFF keys, whose CRS then becomes the WKT the writers give a
// foreign file (io/src/las/crs_wkt.cpp, PROJ's EPSG database), read back by crsFromWkt.
//
// Input: byte 0 even, the rest is a WKT payload; odd, bytes 1-2 and 3-4 are the lengths
// (little-endian, cut to what follows) of the key directory and the doubles records, then
// the directory, the doubles and the ASCII record (the rest). Seeds: fuzz/seeds/las_crs
// (make_seeds.py: the records of tests/data/real's files and crafted ones).
//
// The contract: no throw (the parsers never throw), no crash and nothing ASan or UBSan
// flags; a CRS read (source "wkt" or "geotiff") has no problem, one not read has a
// problem of one printable ASCII line; its kind is one of the six; every unit's length is
// finite and not negative, and 0 for an angle; codes are not negative; the texts taken
// from the input are no longer than it. A WKT the writers make of the keys reads back as
// a CRS of the same EPSG code (or of none, where the keys' unit altered it), on one line.
#include "check_message.hpp"

#include <io/las_crs.hpp>

#include "../io/src/las/crs_wkt.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>

namespace {

[[noreturn]] void fail(const char* what, const std::string& detail) {
    std::fprintf(stderr, "fuzz_las_crs: %s: %.300s\n", what, detail.c_str());
    std::abort();
}

void checkUnit(const io::CrsUnit& u, std::size_t input_size) {
    if (!std::isfinite(u.metres) || u.metres < 0.0) fail("a unit's length is not finite and >= 0", u.name);
    if (u.angular && u.metres != 0.0) fail("an angular unit has a length in metres", u.name);
    if (u.epsg < 0) fail("a unit's EPSG code is negative", u.name);
    if (u.name.size() > input_size + 40) fail("a unit's name is longer than the input", u.name);
}

void checkCrs(const io::LasCrs& crs, std::size_t input_size) {
    const bool read = !crs.source.empty();
    if (read && crs.source != "wkt" && crs.source != "geotiff") fail("unknown source", crs.source);
    if (read != crs.problem.empty()) fail("a CRS read with a problem, or none read without one", crs.problem);
    if (!crs.problem.empty()) fuzz::checkMessage(crs.problem.c_str(), true);
    const std::string_view kinds[] = {"", "projected", "geographic", "geocentric", "compound", "vertical"};
    bool known = false;
    for (std::string_view k : kinds) known = known || crs.kind == k;
    if (!known) fail("unknown kind", crs.kind);
    if (crs.epsg < 0 || crs.vertical_epsg < 0) fail("a negative EPSG code", crs.name);
    if (crs.name.size() > input_size || crs.vertical_name.size() > input_size)
        fail("a name longer than the input", crs.name);
    checkUnit(crs.horizontal_unit, input_size);
    checkUnit(crs.vertical_unit, input_size);
}

std::uint16_t le16(const std::uint8_t* p) { return std::uint16_t(p[0] | (p[1] << 8)); }

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size == 0) return 0;
    const std::string_view rest(reinterpret_cast<const char*>(data) + 1, size - 1);
    if ((data[0] & 1u) == 0) {
        checkCrs(io::crsFromWkt(rest), rest.size());
        return 0;
    }
    if (size < 5) return 0;
    std::string_view tail = rest.substr(4);
    const std::size_t directory_bytes = std::min<std::size_t>(le16(data + 1), tail.size());
    const std::string_view directory = tail.substr(0, directory_bytes);
    tail = tail.substr(directory_bytes);
    const std::size_t doubles_bytes = std::min<std::size_t>(le16(data + 3), tail.size());
    const std::string_view doubles = tail.substr(0, doubles_bytes);
    const std::string_view ascii = tail.substr(doubles_bytes);
    const io::LasCrs crs = io::crsFromGeoKeys(directory, doubles, ascii);
    checkCrs(crs, size);
    if (crs.source.empty()) return 0;
    std::string problem;
    const std::string wkt = io::detail::wktForCrs(crs, problem);
    if (wkt.empty()) {
        if (problem.empty()) fail("no WKT and no problem", crs.name);
        fuzz::checkMessage(problem.c_str(), true);
        return 0;
    }
    for (const char c : wkt)
        if (c == '\n' || c == '\r') fail("the WKT made of the keys is not one line", wkt);
    const io::LasCrs back = io::crsFromWkt(wkt);
    if (back.source != "wkt") fail("the WKT made of the keys does not read back", back.problem + " in " + wkt);
    if (back.epsg != crs.epsg && back.epsg != 0)
        fail("the WKT made of the keys names another EPSG code", std::to_string(back.epsg) + " in " + wkt);
    return 0;
}
