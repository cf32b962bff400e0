// engine/point_cloud.hpp: the fused cloud in memory.
#pragma once
#include <engine/frames.hpp>
#include <engine/scene.hpp>

#include <cstdint>
#include <vector>

namespace engine {

/// One Ladar return. Position in the cloud's local frame (world - origin).
struct CloudPoint {
    glm::vec3 position{0.0f};
    std::uint32_t rgb = 0xFFFFFFu;   // 0x00RRGGBB
    float range_m = 0.0f;            // sensor-to-hit distance
    std::uint16_t view = 0;          // index of the drone position, 0..NoV-1
    Role label = Role::Environment;  // ground truth: the role of the mesh hit
};

/// Which optional fields a cloud carries (files from elsewhere may have only x y z).
struct CloudFields {
    bool rgb = true;
    bool label = true;
    bool view = true;
    bool range = true;
};

struct PointCloud {
    glm::dvec3 origin{0.0};          // world coordinates of the local frame's origin
    CloudFields fields;
    std::vector<CloudPoint> points;

    Bounds bounds() const;
};

/// Packs 8-bit channels into 0x00RRGGBB.
constexpr std::uint32_t packRgb(std::uint8_t r, std::uint8_t g, std::uint8_t b) {
    return (std::uint32_t(r) << 16) | (std::uint32_t(g) << 8) | std::uint32_t(b);
}
inline constexpr std::uint32_t kWhite = 0xFFFFFFu;

}  // namespace engine
