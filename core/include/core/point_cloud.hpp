// core/point_cloud.hpp: the fused cloud in memory.
#pragma once
#include <core/frames.hpp>
#include <core/scene.hpp>

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace core {

/// One Ladar return. Position in the cloud's local frame (world - origin).
/// The fields after range_m are filled by realistic sensor models, ground filters and
/// readers of real data; CloudFields says which ones a cloud carries. The layout has no
/// padding (checked below), so two clouds compare byte for byte.
struct CloudPoint {
    glm::vec3 position{0.0f};
    std::uint32_t rgb = 0xFFFFFFu;       // 0x00RRGGBB
    float range_m = 0.0f;                // sensor-to-hit distance
    float incidence_deg = 0.0f;          // angle between the beam and the surface normal
    float scan_angle_deg = 0.0f;         // angle between the beam and the sensor's boresight
    float height_above_ground_m = 0.0f;  // above the fitted terrain surface
    std::uint16_t intensity = 0;         // return strength, 0..65535 (the LAS convention)
    std::uint16_t view = 0;              // index of the drone position, 0..NoV-1
    Role label = Role::Environment;      // ground truth: the role of the mesh hit
    std::uint8_t return_number = 1;      // 1-based rank of this return within its pulse
    std::uint8_t returns = 1;            // number of returns of its pulse
    std::uint8_t reserved = 0;           // always 0: keeps the layout free of padding
};
static_assert(sizeof(CloudPoint) == 40, "CloudPoint must have no padding bytes");

/// Which optional fields a cloud carries (files from elsewhere may have only x y z).
/// The first four are what the ideal generator writes; the others are off unless a
/// sensor model, ground filter or reader fills them.
struct CloudFields {
    bool rgb = true;
    bool label = true;
    bool view = true;
    bool range = true;
    bool intensity = false;
    bool returns = false;  // return_number and returns
    bool incidence = false;
    bool scan_angle = false;
    bool height_above_ground = false;
};

/// The names of the fields `f` holds, x, y and z first, in the order the writers lay them
/// out ("rgb", "label", "view", "range", "intensity", "returns", "incidence", "scan_angle",
/// "height_above_ground").
std::vector<std::string> fieldNames(const CloudFields& f);

/// What a LAS, LAZ or COPC file made elsewhere holds per point beyond a CloudPoint, so
/// that a file read and written again keeps it. CloudPoint stays small for the clouds we
/// generate; these travel beside the points (ForeignFields) only for files that have them.
struct ForeignPoint {
    double gps_time_s = 0.0;
    /// The integer coordinates the file gave the point (ForeignHeader's scale and offset):
    /// a float position may not hold them (0.1 mm steps 1 km from the origin), so a writer
    /// on the same grid gives them back from here while the point is where they say.
    std::int32_t xyz[3] = {0, 0, 0};
    std::uint16_t rgb[3] = {0, 0, 0};  // colour at the file's 16-bit depth
    std::uint16_t nir = 0;             // near infrared (point formats 8 and 10)
    std::uint16_t point_source_id = 0;
    std::uint8_t classification = 0;  // ASPRS class 0..255
    /// Bits 0-3 the class flags (synthetic, key-point, withheld, overlap), 4-5 the
    /// scanner channel, 6 the scan direction, 7 the edge of flight line.
    std::uint8_t flags = 0;
    std::uint8_t user_data = 0;
    std::uint8_t reserved[7] = {0, 0, 0, 0, 0, 0, 0};  // always 0: no padding bytes
};
static_assert(sizeof(ForeignPoint) == 40, "ForeignPoint must have no padding bytes");

/// What such a file holds once, for the writers: its CRS and its extra bytes' layout.
struct ForeignHeader {
    int point_format = 0;  // the source's LAS point format (0..10)
    bool nir = false;      // its records hold near infrared
    /// Its scale and offset per axis: writers that use them give each point the integer
    /// coordinates it had. A scale of 0 leaves the writer's own (1 mm, the cloud origin).
    glm::dvec3 scale{0.0}, offset{0.0};
    /// The payload of its extra bytes VLR (192-byte descriptors), as the file holds it, and
    /// the bytes a record has after its format's fields (all of them kept, described or not).
    std::string extra_bytes_vlr;
    std::size_t extra_bytes = 0;
    /// The CRS as OGC WKT: the file's WKT record as it is, or one made from its GeoTIFF
    /// keys' EPSG code; empty when it has none.
    std::string wkt;
    /// Why a CRS the file declares could not be given as WKT; empty otherwise.
    std::string crs_problem;
    /// Its header's system identifier (the hardware that collected the points, as its
    /// producer named it; at most 32 bytes), written back in place of ours.
    std::string system_identifier;
    /// Bytes of one point's side record: a ForeignPoint, then the extra bytes.
    std::size_t stride() const { return sizeof(ForeignPoint) + extra_bytes; }
};

/// A foreign file's per-point side records, point k's at records[k * header.stride()].
struct ForeignFields {
    ForeignHeader header;
    std::vector<unsigned char> records;
};

struct PointCloud {
    glm::dvec3 origin{0.0};  // world coordinates of the local frame's origin
    CloudFields fields;
    std::vector<CloudPoint> points;
    /// Set only for a cloud read from another producer's LAS/LAZ/COPC file by a reader
    /// asked to keep it; one record per point, in the points' order.
    std::optional<ForeignFields> foreign;

    Bounds bounds() const;
};

/// Packs 8-bit channels into 0x00RRGGBB.
constexpr std::uint32_t packRgb(std::uint8_t r, std::uint8_t g, std::uint8_t b) {
    return (std::uint32_t(r) << 16) | (std::uint32_t(g) << 8) | std::uint32_t(b);
}
inline constexpr std::uint32_t kWhite = 0xFFFFFFu;

}  // namespace core
