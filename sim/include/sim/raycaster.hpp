// sim/raycaster.hpp: first-hit ray casting against a Scene with Embree 4 (paper §III-B).
// Every Embree call lives in sim/src/raycaster.cpp; callers see only these types.
#pragma once
#include <core/scene.hpp>

#include <cstdint>
#include <memory>
#include <span>

namespace sim {

/// A ray in the scene's local frame; `direction` need not be unit length
/// (then `t` is in units of its length).
struct Ray {
    glm::vec3 origin{0.0f};
    glm::vec3 direction{0.0f, 0.0f, -1.0f};
    float t_far = 1e30f;
};

/// The first hit of a ray. mesh < 0 means a miss.
struct Hit {
    float t = 0.0f;              // distance along the ray, in units of |direction|
    std::int32_t mesh = -1;      // index into Scene::meshes
    std::uint32_t triangle = 0;  // triangle index inside that mesh
    core::Role role = core::Role::Environment;
    glm::vec3 normal{0.0f};  // the triangle's geometric normal (not unit length)
    bool hit() const { return mesh >= 0; }
};

/// Builds one Embree BVH (RTC_SCENE_FLAG_ROBUST, high quality) over every mesh of the
/// scene. Throws core::Error("embree: ...") on device or build errors.
class RayCaster {
  public:
    explicit RayCaster(const core::Scene& scene);
    /// Only the meshes whose role is in `roles` (the others are never hit; geomID is
    /// still the index into Scene::meshes). Throws core::Error("embree: ...").
    RayCaster(const core::Scene& scene, core::RoleMask roles);
    ~RayCaster();
    RayCaster(const RayCaster&) = delete;
    RayCaster& operator=(const RayCaster&) = delete;

    /// Traces rays[i] into hits[i] (same size). Thread-safe: several threads may call
    /// this concurrently on disjoint spans. Does not spawn threads itself.
    void intersect(std::span<const Ray> rays, std::span<Hit> hits) const;
    /// The same hits, traced as rtcIntersect16 packets of 16 consecutive rays (the last
    /// one partial) with the coherent-ray flag, as the generator traces pixel rows.
    void intersect16(std::span<const Ray> rays, std::span<Hit> hits) const;

    /// Local-frame bounds of all geometry.
    core::Bounds bounds() const;

    /// Triangles in the BVH.
    std::size_t triangleCount() const;

    struct Impl;  // Embree's state, defined in sim/src/raycaster.cpp only
  private:
    std::unique_ptr<Impl> impl_;
};

}  // namespace sim
