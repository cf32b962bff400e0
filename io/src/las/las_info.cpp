// io/src/las/las_info.cpp: the LAS, LAZ and COPC part of io::inspectCloud. The LAS reader
// checks the header and the VLRs and records them (las_facts.hpp) and its records are
// counted as it decodes them, a chunk at a time; what the VLRs say (the CRS, the extra
// bytes fields) is then read from payloads the reader has placed inside the file.
#include "las_facts.hpp"

#include <core/error.hpp>
#include <io/copc.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <optional>
#include <deque>

namespace io {

std::string asprsClassName(unsigned code, int las_minor) {
    static constexpr std::array<const char*, 23> kNames = {"never classified",
                                                           "unclassified",
                                                           "ground",
                                                           "low vegetation",
                                                           "medium vegetation",
                                                           "high vegetation",
                                                           "building",
                                                           "low point (noise)",
                                                           "reserved",
                                                           "water",
                                                           "rail",
                                                           "road surface",
                                                           "reserved",
                                                           "wire - guard (shield)",
                                                           "wire - conductor (phase)",
                                                           "transmission tower",
                                                           "wire-structure connector",
                                                           "bridge deck",
                                                           "high noise",
                                                           "overhead structure",
                                                           "ignored ground",
                                                           "snow",
                                                           "temporal exclusion"};
    if (las_minor < 4 && code == 8) return "model key-point";
    if (las_minor < 4 && code == 12) return "overlap";
    if (code < kNames.size()) return kNames[code];
    return code < 64 ? "reserved" : "user-defined";
}

namespace detail {
namespace {

constexpr std::size_t kChunkPoints = 1u << 16;
// The most of a WKT or GeoTIFF record read (an EVLR may declare gigabytes; a CRS is a
// few kilobytes).
constexpr std::uint64_t kMaxCrsBytes = 1u << 20;
constexpr std::size_t kExtraBytesDescriptor = 192;

std::string payload(ByteSource& source, const LasVlrPlace& v, std::uint64_t most) {
    return std::string(source.view(v.payload_at, std::size_t(std::min(v.bytes, most))));
}

const LasVlrPlace* findRecord(const LasFacts& facts, std::uint16_t record) {
    for (const LasVlrPlace& v : facts.vlrs)
        if (v.user == "LASF_Projection" && v.record == record) return &v;
    return nullptr;
}

}  // namespace

// The CRS from the WKT record, else from the GeoTIFF keys; the problems of both when
// neither gives one.
LasCrs readCrs(ByteSource& source, const LasFacts& facts) {
    LasCrs wkt, geotiff;
    if (const LasVlrPlace* v = findRecord(facts, 2112)) {
        if (v->bytes > kMaxCrsBytes)
            wkt.problem = "the WKT record is larger than 1 MiB";
        else
            wkt = crsFromWkt(payload(source, *v, kMaxCrsBytes));
        if (!wkt.source.empty()) return wkt;
    }
    if (const LasVlrPlace* v = findRecord(facts, 34735)) {
        const LasVlrPlace* doubles = findRecord(facts, 34736);
        const LasVlrPlace* ascii = findRecord(facts, 34737);
        geotiff = crsFromGeoKeys(payload(source, *v, kMaxCrsBytes),
                                 doubles ? payload(source, *doubles, kMaxCrsBytes) : std::string(),
                                 ascii ? payload(source, *ascii, kMaxCrsBytes) : std::string());
        if (!geotiff.source.empty()) return geotiff;
    }
    LasCrs none;
    none.problem = wkt.problem;
    if (!geotiff.problem.empty()) none.problem += (none.problem.empty() ? "" : "; ") + geotiff.problem;
    return none;
}

LasCrs readLasCrs(ByteSource& source, const std::string& prefix) {
    LasFacts facts;
    LasTally tally;
    openLasCounted(source, prefix, facts, tally);  // the header and the records' places checked
    return readCrs(source, facts);
}

namespace {

// A little-endian value at `at` of `d` (x86-64 and aarch64 are little-endian, as LAS is).
template <class T>
T valueAt(const std::string& d, std::size_t at) {
    T v;
    std::memcpy(&v, d.data() + at, sizeof v);
    return v;
}

// The optional values of a descriptor of a single value of `type` (1..10): "anytype"
// fields (8 bytes) that hold an unsigned, a signed or a floating value as the type is.
void describeValues(const std::string& d, unsigned type, LasExtraField& f) {
    const unsigned options = std::uint8_t(d[3]);
    const auto any = [&](std::size_t at) {
        if (type == 9 || type == 10) return valueAt<double>(d, at);
        if (type % 2 == 0) return double(valueAt<std::int64_t>(d, at));  // int8, int16, int32, int64
        return double(valueAt<std::uint64_t>(d, at));
    };
    const auto finite = [](double v) { return std::isfinite(v) ? std::optional<double>(v) : std::nullopt; };
    if (options & 1u) f.no_data = finite(any(40));
    if (options & 2u) f.min = finite(any(64));
    if (options & 4u) f.max = finite(any(88));
    if (options & 8u) f.scale = finite(valueAt<double>(d, 112));
    if (options & 16u) f.offset = finite(valueAt<double>(d, 136));
}

// The fields of the extra bytes VLR's descriptors.
std::vector<LasExtraField> readExtraFields(ByteSource& source, const LasFacts& facts) {
    static constexpr std::array<const char*, 11> kTypes = {"",      "uint8",  "int8",  "uint16",  "int16",  "uint32",
                                                           "int32", "uint64", "int64", "float32", "float64"};
    static constexpr std::array<std::size_t, 11> kSizes = {0, 1, 1, 2, 2, 4, 4, 8, 8, 4, 8};
    std::vector<LasExtraField> fields;
    for (const LasVlrPlace& v : facts.vlrs) {
        if (v.user != "LASF_Spec" || v.record != 4) continue;
        const std::string p = payload(source, v, v.bytes);  // a VLR: at most 65,535 bytes
        for (std::size_t d = 0; d + kExtraBytesDescriptor <= p.size(); d += kExtraBytesDescriptor) {
            const unsigned type = std::uint8_t(p[d + 2]);
            LasExtraField f;
            f.name = core::printable(std::string_view(p.data() + d + 4, strnlen(p.data() + d + 4, 32)), 40);
            f.description = core::printable(std::string_view(p.data() + d + 160, strnlen(p.data() + d + 160, 32)), 40);
            if (type == 0) {
                f.bytes = std::uint8_t(p[d + 3]);  // undocumented: the options field holds the size
                f.type = std::to_string(f.bytes) + " bytes";
            } else if (type <= 10) {
                f.bytes = kSizes[type];
                f.type = kTypes[type];
                describeValues(p.substr(d, kExtraBytesDescriptor), type, f);
            } else if (type <= 30) {  // deprecated arrays of 2 or 3
                const unsigned base = (type - 1) % 10 + 1, n = (type - 1) / 10 + 1;
                f.bytes = kSizes[base] * n;
                f.type = std::string(kTypes[base]) + "[" + std::to_string(n) + "]";
            } else {
                f.type = "type " + std::to_string(type) + " (not one of 0 to 30)";
            }
            fields.push_back(std::move(f));
        }
    }
    return fields;
}

// The dimensions of a point format (LAS 1.4 R15 tables 7 to 16), PDAL's names.
std::vector<std::string> formatFields(unsigned format) {
    std::vector<std::string> f = {"X", "Y", "Z", "Intensity", "ReturnNumber", "NumberOfReturns"};
    const bool extended = format >= 6;
    if (extended) f.insert(f.end(), {"ClassFlags", "ScannerChannel"});
    f.insert(f.end(), {"ScanDirectionFlag", "EdgeOfFlightLine", "Classification", "UserData",
                       extended ? "ScanAngle" : "ScanAngleRank", "PointSourceId"});
    if (format != 0 && format != 2) f.push_back("GpsTime");
    if (format == 2 || format == 3 || format == 5 || format == 7 || format == 8 || format == 10)
        f.insert(f.end(), {"Red", "Green", "Blue"});
    if (format == 8 || format == 10) f.push_back("Infrared");
    if (format == 4 || format == 5 || format == 9 || format == 10)
        f.insert(f.end(), {"WavePacketDescriptorIndex", "WaveformDataOffset", "WaveformPacketSize",
                           "ReturnPointWaveformLocation", "XT", "YT", "ZT"});
    return f;
}

// The nodes with points of a COPC file's hierarchy, its pages read one at a time.
std::uint64_t copcNodes(const std::filesystem::path& file, const std::string& prefix) {
    try {
        const CopcReader reader(file, CopcHierarchy::by_page);
        std::uint64_t nodes = reader.nodes().size();
        std::deque<CopcPage> pages(reader.pages().begin(), reader.pages().end());
        while (!pages.empty()) {
            const CopcPageEntries e = reader.readPage(pages.front());
            pages.pop_front();
            nodes += e.nodes.size();
            pages.insert(pages.end(), e.pages.begin(), e.pages.end());
        }
        return nodes;
    } catch (const core::Error& e) {
        // "copc: <file>: <rule>: ..." as this file's: "<prefix>: COPC <rule>: ...".
        std::string m = e.what();
        const std::string own = "copc: " + file.string() + ": ";
        if (m.rfind(own, 0) == 0) m = m.substr(own.size());
        throw core::Error(prefix + ": COPC " + m);
    }
}

}  // namespace

void inspectLas(ByteSource& source, const std::string& prefix, const std::filesystem::path& file, CloudInfo& info,
                const InspectProgress& progress) {
    LasFacts facts;
    LasTally tally;
    // Bins for gaps of kStrayGap_m in metres or in any shorter unit (feet): the span is
    // read with the file's own unit once its CRS is known, after the points.
    core::HeightSpan heights(core::kStrayGap_m);
    {
        const std::unique_ptr<FormatReader> reader = openLasCounted(source, prefix, facts, tally);
        std::vector<core::CloudPoint> chunk;
        chunk.reserve(kChunkPoints);
        std::uint64_t read = 0;
        while (reader->next(chunk, kChunkPoints) > 0) {
            for (const core::CloudPoint& p : chunk) heights.add(float(double(p.position.z) + reader->origin.z));
            read += chunk.size();
            chunk.clear();
            if (progress) progress(read, reader->declared);
        }
    }
    LasInfo las;
    las.version_major = facts.major;
    las.version_minor = facts.minor;
    las.point_format = facts.point_format;
    las.record_bytes = facts.record_bytes;
    las.compressed = facts.compressed;
    las.legacy_points = facts.legacy_points;
    if (facts.minor >= 4) las.points_64 = facts.points_64;
    las.scale = facts.scale;
    las.offset = facts.offset;
    for (std::size_t k = 0; k < 3 && tally.points > 0; ++k) {
        las.points_min[int(k)] = double(tally.xyz_min[k]) * facts.scale[int(k)] + facts.offset[int(k)];
        las.points_max[int(k)] = double(tally.xyz_max[k]) * facts.scale[int(k)] + facts.offset[int(k)];
    }
    las.system_id = core::printable(facts.system_id, 40);
    las.software = core::printable(facts.software, 40);
    las.creation_day = facts.creation_day;
    las.creation_year = facts.creation_year;
    for (const LasVlrPlace& v : facts.vlrs)
        las.records.push_back(
            {core::printable(v.user, 40), v.record, core::printable(v.description, 40), v.bytes, v.extended});
    las.crs = readCrs(source, facts);
    const CrsUnit& z_unit = las.crs.vertical_unit.metres > 0.0 ? las.crs.vertical_unit : las.crs.horizontal_unit;
    las.heights = heights.span(core::kStrayGap_m / (z_unit.metres > 0.0 ? z_unit.metres : 1.0));
    // A side without strays: the points' own extreme, exactly (the span holds floats).
    if (las.heights.strays_low == 0) las.heights.lo = las.points_min.z;
    if (las.heights.strays_high == 0) las.heights.hi = las.points_max.z;
    for (unsigned c = 0; c < tally.classes.size(); ++c)
        if (tally.classes[c] > 0) las.classes[c] = tally.classes[c];
    for (unsigned r = 0; r < tally.returns.size(); ++r)
        if (tally.returns[r] > 0) las.returns[r] = tally.returns[r];
    las.extra_fields = readExtraFields(source, facts);
    const unsigned f = facts.point_format;
    if (f == 2 || f == 3 || f == 5 || f == 7 || f == 8 || f == 10) {
        las.rgb_max = {tally.rgb_max[0], tally.rgb_max[1], tally.rgb_max[2]};
        const unsigned most = *std::max_element(las.rgb_max.begin(), las.rgb_max.end());
        las.colour = colourDepthOf(most);
    }
    las.copc = isCopcFile(file);
    if (las.copc) las.copc_nodes = copcNodes(file, prefix);

    info.format = las.copc ? "COPC" : facts.compressed ? "LAZ" : "LAS";
    info.version = std::to_string(facts.major) + "." + std::to_string(facts.minor);
    info.points = tally.points;
    info.has_bounds = true;
    info.min = facts.min;
    info.max = facts.max;
    info.fields = formatFields(f);
    for (const LasExtraField& e : las.extra_fields) info.fields.push_back(e.name);
    info.las = std::move(las);
}

}  // namespace detail
}  // namespace io
