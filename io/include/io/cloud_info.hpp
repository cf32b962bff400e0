// io/cloud_info.hpp: what a cloud file holds, as `ladarvr info` reports it (pdal info,
// lasinfo): for every format the format, point count, bounds and fields; for LAS, LAZ
// and COPC also the header's version, point format, counts, scale and offset, the CRS
// and its units (io/las_crs.hpp), the ASPRS classes and return numbers of the points,
// the extra bytes fields, the colour depth, the point density and the COPC nodes.
// The whole file is read once, in chunks, through the same checked readers as
// CloudReader (LAZ decoded in their separate process), so memory stays bounded.
#pragma once
#include <core/height_span.hpp>
#include <io/las_crs.hpp>

#include <glm/vec3.hpp>

#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace io {

/// One field described by a LAS extra bytes VLR (LAS 1.4 R15 §2.5.2.6).
struct LasExtraField {
    std::string name;
    std::string type;  // "uint8", ..., "float64"; "N bytes" for undocumented bytes
    std::size_t bytes = 0;
    std::string description;
    /// What the descriptor's options say it holds (absent where its bit is clear): the
    /// no-data value, minimum and maximum as stored (before the scale and offset), and the
    /// scale and offset that give a value from a stored one (value = stored x scale +
    /// offset). Of a single value (types 1 to 10) only.
    std::optional<double> no_data, min, max, scale, offset;
};

/// One VLR or EVLR of a LAS file.
struct LasRecordInfo {
    std::string user;
    unsigned record = 0;
    std::string description;
    std::uint64_t bytes = 0;  // of its payload
    bool extended = false;    // an EVLR (after the points)
};

/// What 16-bit RGB fields hold.
enum class ColourDepth {
    None,        // the point format has no RGB
    Zero,        // every value is 0
    EightBit,    // every value is <= 255: 8-bit values in 16-bit fields
    SixteenBit,  // some value is > 255
};

/// The depth of a file's colours from the largest red, green or blue value it holds (as
/// CloudCompare reads them: none over 255 means 8-bit values in 16-bit fields).
constexpr ColourDepth colourDepthOf(unsigned largest) {
    return largest == 0 ? ColourDepth::Zero : largest <= 255 ? ColourDepth::EightBit : ColourDepth::SixteenBit;
}

/// LAS, LAZ and COPC only.
struct LasInfo {
    int version_major = 1, version_minor = 0;
    unsigned point_format = 0;
    std::size_t record_bytes = 0;
    bool compressed = false;
    std::uint64_t legacy_points = 0;         // the header's 32-bit count
    std::optional<std::uint64_t> points_64;  // LAS 1.4's 64-bit count
    glm::dvec3 scale{1.0}, offset{0.0};
    glm::dvec3 points_min{0.0}, points_max{0.0};  // of the points read (empty file: 0)
    std::string system_id, software;
    unsigned creation_day = 0, creation_year = 0;
    std::vector<LasRecordInfo> records;
    LasCrs crs;                                 // source empty: no CRS (problem says why when a record was there)
    std::map<unsigned, std::uint64_t> classes;  // ASPRS class -> points
    std::map<unsigned, std::uint64_t> returns;  // return number -> points
    std::vector<LasExtraField> extra_fields;
    ColourDepth colour = ColourDepth::None;
    std::array<unsigned, 3> rgb_max{};  // the largest red, green, blue value
    bool copc = false;
    std::uint64_t copc_nodes = 0;  // COPC: nodes of the hierarchy holding points
    /// The points' heights without their stray returns (core::HeightSpan, a gap of at least
    /// core::kStrayGap_m in the file's height unit: its vertical unit, else its horizontal
    /// one, else metres); world coordinates. No points: all zero.
    core::HeightSpan::Span heights;
};

struct CloudInfo {
    std::filesystem::path file;
    std::uint64_t file_bytes = 0;
    std::string format;            // "LAS", "LAZ", "COPC", "PCD", "PLY"
    std::string version;           // "1.2" (LAS), "0.7" (PCD), "1.0" (PLY); empty if not stated
    std::string encoding;          // PCD and PLY: "ascii", "binary", "binary_compressed", "binary_little_endian", ...
    std::uint64_t points = 0;      // the records read (non-finite ones included)
    std::uint64_t non_finite = 0;  // PCD and PLY: points with a non-finite x, y or z
    /// LAS: the header's bounds; PCD and PLY: those of the finite points (world coordinates).
    bool has_bounds = false;
    glm::dvec3 min{0.0}, max{0.0};
    std::vector<std::string> fields;  // the fields each point has, as the format names them
    std::optional<LasInfo> las;
};

/// Told after each chunk of points read: the points read so far and the header's count.
using InspectProgress = std::function<void(std::uint64_t read, std::uint64_t declared)>;

/// Reads `file` (PCD, PLY, LAS, LAZ or COPC; the content decides, as CloudReader) and
/// describes it, telling `progress` (when given) as its points are read. Throws
/// core::Error("<context>: <file>: what is wrong"), naming the field and what is
/// allowed, for a file that cannot be read.
CloudInfo inspectCloud(const std::filesystem::path& file, const char* context, const InspectProgress& progress = {});

/// Where a cloud's points lie, as inspectCloud gives them (has_bounds, min, max).
struct CloudBounds {
    bool has_bounds = false;
    glm::dvec3 min{0.0}, max{0.0};
};
/// inspectCloud's bounds of `file`, reading only what they need: a LAS, LAZ or COPC
/// file's header (checked as inspectCloud checks it; its points are not decoded), every
/// point of a PCD or PLY file. Throws core::Error as inspectCloud.
CloudBounds readCloudBounds(const std::filesystem::path& file, const char* context);

/// The CRS `file` declares, only its header and VLRs read: a LAS, LAZ or COPC file's WKT
/// record, else its GeoTIFF keys (as inspectCloud reads them); source empty for PCD and
/// PLY (they state none) and for a LAS file without one. Throws core::Error as inspectCloud.
LasCrs readCloudCrs(const std::filesystem::path& file, const char* context);

/// The ASPRS name of a classification code (LAS 1.4 R15 table 17; for files before LAS
/// 1.4, classes 8 and 12 as LAS 1.0-1.3 define them): "ground", "building", ...,
/// "reserved", "user-defined".
std::string asprsClassName(unsigned code, int las_minor);

}  // namespace io
