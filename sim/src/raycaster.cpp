// sim/raycaster.cpp: first-hit ray casting with Embree 4 (paper §III-B: "we use the
// principle of ray casting ... for each pixel ... we launch a virtual ray").
#include <sim/raycaster.hpp>

#include <embree4/rtcore.h>

#include <core/error.hpp>

#include <algorithm>
#include <cassert>
#include <mutex>
#include <string>
#include <vector>

namespace sim {

struct RayCaster::Impl {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    std::vector<core::Role> roles;  // by geomID (== mesh index)
    core::Bounds bounds;
    std::size_t triangles = 0;
    std::mutex error_mutex;
    std::string first_error;  // recorded by the device error callback

    ~Impl();
};

namespace {

/// Fills an Embree ray/hit record for a first-hit query from `origin` along `direction`.
void setRay(RTCRayHit& rh, float ox, float oy, float oz, float dx, float dy, float dz, float t_far) {
    rh.ray.org_x = ox;
    rh.ray.org_y = oy;
    rh.ray.org_z = oz;
    rh.ray.tnear = 0.0f;
    rh.ray.dir_x = dx;
    rh.ray.dir_y = dy;
    rh.ray.dir_z = dz;
    rh.ray.time = 0.0f;
    rh.ray.tfar = t_far;
    rh.ray.mask = 0xFFFFFFFFu;
    rh.ray.id = 0;
    rh.ray.flags = 0;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
}

/// The same for lane `k` of a 16-ray packet.
void setPacketRay(RTCRayHit16& rh, std::size_t k, const glm::vec3& origin, const glm::vec3& direction, float t_far) {
    rh.ray.org_x[k] = origin.x;
    rh.ray.org_y[k] = origin.y;
    rh.ray.org_z[k] = origin.z;
    rh.ray.tnear[k] = 0.0f;
    rh.ray.dir_x[k] = direction.x;
    rh.ray.dir_y[k] = direction.y;
    rh.ray.dir_z[k] = direction.z;
    rh.ray.time[k] = 0.0f;
    rh.ray.tfar[k] = t_far;
    rh.ray.mask[k] = 0xFFFFFFFFu;
    rh.ray.id[k] = unsigned(k);
    rh.ray.flags[k] = 0;
    rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
}

const char* errorName(RTCError code) {
    switch (code) {
        case RTC_ERROR_NONE: return "no error";
        case RTC_ERROR_UNKNOWN: return "unknown error";
        case RTC_ERROR_INVALID_ARGUMENT: return "invalid argument";
        case RTC_ERROR_INVALID_OPERATION: return "invalid operation";
        case RTC_ERROR_OUT_OF_MEMORY: return "out of memory";
        case RTC_ERROR_UNSUPPORTED_CPU: return "unsupported CPU";
        case RTC_ERROR_CANCELLED: return "cancelled";
        default: return "error";
    }
}

void onDeviceError(void* user, RTCError code, const char* message) {
    auto* impl = static_cast<RayCaster::Impl*>(user);
    std::lock_guard lock(impl->error_mutex);
    if (impl->first_error.empty())
        impl->first_error = std::string(errorName(code)) + (message ? std::string(": ") + message : "");
}

// CHECK for Embree calls: after `what`, throws with the recorded message (or the
// device's error code) and the call site.
void check(RayCaster::Impl& impl, const char* what, const char* file, int line) {
    const RTCError code = rtcGetDeviceError(impl.device);
    std::string message;
    {
        std::lock_guard lock(impl.error_mutex);
        message = impl.first_error;
    }
    if (code == RTC_ERROR_NONE && message.empty()) return;
    if (message.empty()) message = errorName(code);
    throw core::Error(std::string("embree: ") + what + ": " + message + " (" + file + ":" + std::to_string(line) + ")");
}
#define SIM_EMBREE_CHECK(impl, what) check(impl, what, __FILE__, __LINE__)

}  // namespace

RayCaster::Impl::~Impl() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
}

RayCaster::RayCaster(const core::Scene& scene) : RayCaster(scene, core::RoleMask::all()) {}

RayCaster::RayCaster(const core::Scene& scene, core::RoleMask roles) : impl_(std::make_unique<Impl>()) {
    Impl& impl = *impl_;
    // No threads of our own: Embree's build uses its TBB pool; callers parallelise traversal.
    impl.device = rtcNewDevice(nullptr);
    if (!impl.device)
        throw core::Error(std::string("embree: rtcNewDevice failed: ") + errorName(rtcGetDeviceError(nullptr)));
    rtcSetDeviceErrorFunction(impl.device, onDeviceError, &impl);
    impl.scene = rtcNewScene(impl.device);
    rtcSetSceneFlags(impl.scene, RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(impl.scene, RTC_BUILD_QUALITY_HIGH);
    SIM_EMBREE_CHECK(impl, "rtcNewScene");

    impl.roles.resize(scene.meshes.size(), core::Role::Environment);
    for (std::size_t m = 0; m < scene.meshes.size(); ++m) {
        const core::Mesh& mesh = scene.meshes[m];
        impl.roles[m] = mesh.role;
        if (!roles.has(mesh.role) || mesh.triangles.empty() || mesh.vertices.empty()) continue;
        const std::size_t nv = mesh.vertices.size();
        for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
            const glm::uvec3& tri = mesh.triangles[t];
            if (tri.x >= nv || tri.y >= nv || tri.z >= nv)
                throw core::Error("embree: mesh '" + mesh.name + "': triangle " + std::to_string(t) +
                                  " indexes a vertex past " + std::to_string(nv));
        }
        RTCGeometry geom = rtcNewGeometry(impl.device, RTC_GEOMETRY_TYPE_TRIANGLE);
        // Embree-allocated buffers carry the padding its SIMD loads need.
        auto* vertices = static_cast<float*>(
            rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), nv));
        auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                       3 * sizeof(unsigned), mesh.triangles.size()));
        if (!vertices || !indices) {
            rtcReleaseGeometry(geom);
            SIM_EMBREE_CHECK(impl, "rtcSetNewGeometryBuffer");
            throw core::Error("embree: mesh '" + mesh.name + "': cannot allocate buffers");
        }
        for (std::size_t v = 0; v < nv; ++v) {
            const glm::vec3& p = mesh.vertices[v];
            vertices[3 * v] = p.x;
            vertices[3 * v + 1] = p.y;
            vertices[3 * v + 2] = p.z;
            impl.bounds.extend(glm::dvec3(p));
        }
        for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
            const glm::uvec3& tri = mesh.triangles[t];
            indices[3 * t] = tri.x;
            indices[3 * t + 1] = tri.y;
            indices[3 * t + 2] = tri.z;
        }
        rtcCommitGeometry(geom);
        rtcAttachGeometryByID(impl.scene, geom, static_cast<unsigned>(m));
        rtcReleaseGeometry(geom);
        impl.triangles += mesh.triangles.size();
        SIM_EMBREE_CHECK(impl, ("mesh '" + mesh.name + "'").c_str());
    }
    rtcCommitScene(impl.scene);
    SIM_EMBREE_CHECK(impl, "rtcCommitScene");
}

RayCaster::~RayCaster() = default;

void RayCaster::intersect(std::span<const Ray> rays, std::span<Hit> hits) const {
    const Impl& impl = *impl_;
    assert(rays.size() == hits.size());
    const std::size_t n = std::min(rays.size(), hits.size());
    RTCRayHit rh;
    for (std::size_t i = 0; i < n; ++i) {
        const Ray& r = rays[i];
        setRay(rh, r.origin.x, r.origin.y, r.origin.z, r.direction.x, r.direction.y, r.direction.z, r.t_far);
        rtcIntersect1(impl.scene, &rh);
        Hit& h = hits[i];
        if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) {
            h = Hit{};
        } else {
            h.t = rh.ray.tfar;
            h.mesh = static_cast<std::int32_t>(rh.hit.geomID);
            h.triangle = rh.hit.primID;
            h.role = impl.roles[rh.hit.geomID];
            h.normal = glm::vec3(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z);
        }
    }
}

void RayCaster::intersect16(std::span<const Ray> rays, std::span<Hit> hits) const {
    const Impl& impl = *impl_;
    assert(rays.size() == hits.size());
    const std::size_t n = std::min(rays.size(), hits.size());
    RTCRayHit16 rh;
    alignas(64) int valid[16];
    RTCIntersectArguments args;
    rtcInitIntersectArguments(&args);
    args.flags = RTC_RAY_QUERY_FLAG_COHERENT;
    for (std::size_t i = 0; i < n; i += 16) {
        const std::size_t m = std::min<std::size_t>(16, n - i);
        for (std::size_t k = 0; k < 16; ++k) {
            const Ray r = k < m ? rays[i + k] : Ray{};
            valid[k] = k < m ? -1 : 0;
            setPacketRay(rh, k, r.origin, r.direction, r.t_far);
        }
        rtcIntersect16(valid, impl.scene, &rh, &args);
        for (std::size_t k = 0; k < m; ++k) {
            Hit& h = hits[i + k];
            if (rh.hit.geomID[k] == RTC_INVALID_GEOMETRY_ID) {
                h = Hit{};
            } else {
                h.t = rh.ray.tfar[k];
                h.mesh = static_cast<std::int32_t>(rh.hit.geomID[k]);
                h.triangle = rh.hit.primID[k];
                h.role = impl.roles[rh.hit.geomID[k]];
                h.normal = glm::vec3(rh.hit.Ng_x[k], rh.hit.Ng_y[k], rh.hit.Ng_z[k]);
            }
        }
    }
}

core::Bounds RayCaster::bounds() const { return impl_->bounds; }

std::size_t RayCaster::triangleCount() const { return impl_->triangles; }

}  // namespace sim
