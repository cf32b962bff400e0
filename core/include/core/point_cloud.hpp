// core/point_cloud.hpp: the fused cloud in memory.
#pragma once
#include <core/frames.hpp>
#include <core/scene.hpp>

#include <cstdint>
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

struct PointCloud {
    glm::dvec3 origin{0.0};  // world coordinates of the local frame's origin
    CloudFields fields;
    std::vector<CloudPoint> points;

    Bounds bounds() const;
};

/// Packs 8-bit channels into 0x00RRGGBB.
constexpr std::uint32_t packRgb(std::uint8_t r, std::uint8_t g, std::uint8_t b) {
    return (std::uint32_t(r) << 16) | (std::uint32_t(g) << 8) | std::uint32_t(b);
}
inline constexpr std::uint32_t kWhite = 0xFFFFFFu;

}  // namespace core
