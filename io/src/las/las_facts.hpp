// io/src/las/las_facts.hpp (internal): what the LAS/LAZ reader can tell about a file
// besides its points, for `ladarvr info` (las_info.cpp): the header's fields and the
// place of every VLR and EVLR, recorded while the reader checks them (so nothing is
// read that the checks did not bound first), and a tally of the raw point records
// (ASPRS classes, return numbers, 16-bit colours, integer bounds) that the CloudPoints
// it returns do not keep.
#pragma once
#include "cloud_decode.hpp"

#include <io/cloud_info.hpp>

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace io::detail {

/// One VLR (or, `extended`, EVLR): its user id, record id, description and where its
/// payload lies in the file (inside it: the reader checked that).
struct LasVlrPlace {
    std::string user;
    std::uint16_t record = 0;
    std::string description;
    std::uint64_t payload_at = 0;
    std::uint64_t bytes = 0;
    bool extended = false;
};

/// The header's fields, as the file holds them.
struct LasFacts {
    int major = 1, minor = 0;
    unsigned point_format = 0;  // 0..10 (the compression bits cleared)
    bool compressed = false;
    std::size_t record_bytes = 0;
    std::uint64_t legacy_points = 0;  // the 32-bit count
    std::uint64_t points_64 = 0;      // LAS 1.4's 64-bit count (0 before 1.4)
    std::string system_id, software;
    std::uint16_t creation_day = 0, creation_year = 0;
    glm::dvec3 scale{1.0}, offset{0.0}, min{0.0}, max{0.0};
    std::vector<LasVlrPlace> vlrs;  // VLRs, then EVLRs, in file order
};

/// Counts over the point records, as they are in the file. Plain data: the decoding
/// process sends it over its pipe as bytes.
struct LasTally {
    std::uint64_t points = 0;
    std::array<std::uint64_t, 256> classes{};          // [c]: records of ASPRS class c
    std::array<std::uint64_t, 16> returns{};           // [r]: records of return number r
    std::array<std::uint16_t, 3> rgb_max{};            // the largest red, green, blue
    std::array<std::int32_t, 3> xyz_min{}, xyz_max{};  // integer coordinates
};

/// The LAS/LAZ reader (as openLas) that also fills `facts` once the header is checked
/// and counts every record it returns into `tally`; both must outlive the reader. A
/// `label` extra bytes field is not read as our roles (any value is counted).
std::unique_ptr<FormatReader> openLasCounted(ByteSource& source, const std::string& prefix, LasFacts& facts,
                                             LasTally& tally);

/// The CRS of the LAS, LAZ or COPC file open in `source` (its WKT record, else its
/// GeoTIFF keys), only its header and VLRs read. Throws Error("<prefix>: ...").
LasCrs readLasCrs(ByteSource& source, const std::string& prefix);

/// The LAS part of inspectCloud (las_info.cpp): reads every point of the LAS, LAZ or
/// COPC file `file` open in `source` and fills `info`, telling `progress` (when given)
/// after each chunk. Throws Error("<prefix>: ...").
void inspectLas(ByteSource& source, const std::string& prefix, const std::filesystem::path& file, CloudInfo& info,
                const InspectProgress& progress);

}  // namespace io::detail
