// sim/src/raycaster_impl.hpp: RayCaster's Embree state, shared by sim's own sources
// (the generator traces its rays straight into Embree, without an intermediate Ray array).
#pragma once
#include <sim/raycaster.hpp>

#include <embree4/rtcore.h>

#include <mutex>
#include <string>
#include <vector>

namespace sim {

struct RayCaster::Impl {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    std::vector<engine::Role> roles;   // by geomID (== mesh index)
    engine::Bounds bounds;
    std::size_t triangles = 0;
    std::mutex error_mutex;
    std::string first_error;           // recorded by the device error callback

    ~Impl();
};

/// Fills an Embree ray/hit record for a first-hit query from `origin` along `direction`.
inline void setRay(RTCRayHit& rh, float ox, float oy, float oz, float dx, float dy, float dz,
                   float t_far) {
    rh.ray.org_x = ox; rh.ray.org_y = oy; rh.ray.org_z = oz;
    rh.ray.tnear = 0.0f;
    rh.ray.dir_x = dx; rh.ray.dir_y = dy; rh.ray.dir_z = dz;
    rh.ray.time = 0.0f;
    rh.ray.tfar = t_far;
    rh.ray.mask = 0xFFFFFFFFu;
    rh.ray.id = 0;
    rh.ray.flags = 0;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
}

/// The same for lane `k` of a 16-ray packet.
inline void setPacketRay(RTCRayHit16& rh, std::size_t k, const glm::vec3& origin, const glm::vec3& direction,
                         float t_far) {
    rh.ray.org_x[k] = origin.x; rh.ray.org_y[k] = origin.y; rh.ray.org_z[k] = origin.z;
    rh.ray.tnear[k] = 0.0f;
    rh.ray.dir_x[k] = direction.x; rh.ray.dir_y[k] = direction.y; rh.ray.dir_z[k] = direction.z;
    rh.ray.time[k] = 0.0f;
    rh.ray.tfar[k] = t_far;
    rh.ray.mask[k] = 0xFFFFFFFFu;
    rh.ray.id[k] = unsigned(k);
    rh.ray.flags[k] = 0;
    rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
}

}  // namespace sim
