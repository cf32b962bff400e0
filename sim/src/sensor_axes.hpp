// sim/src/sensor_axes.hpp: the pixel axes around a run of beams, and which of those beams
// lie on one plane (their footprint then needs no sub-rays). Used by sim::Sensor's
// footprint path when --footprint-exact is off; see sensor_axes.cpp.
#pragma once
#include <sim/orbit.hpp>
#include <sim/raycaster.hpp>
#include <sim/sensor.hpp>

#include <cstddef>
#include <cstdint>
#include <span>

namespace sim::sensor_model {

/// What fixes the pixel axes' hits, besides the view: the sensor (an id unique in the
/// process, never reused), its pixel grid and its maximum range.
struct AxisSource {
    std::uint64_t sensor_id = 0;
    const OrbitOptions* orbit = nullptr;
    float t_far = 0.0f;
    /// Per pixel (row-major), pixelDirection(*orbit, x, y); empty: computed when needed.
    std::span<const glm::dvec3> directions;
};

/// A new, never-reused AxisSource::sensor_id.
std::uint64_t newSensorId();

/// For the n beams of image row y from column x0 (view v, rays leaving from the pose
/// actually flown): sets planar[i] = 1 where the axes of the beam's 3x3 neighbourhood (one
/// pixel past each end, the rows above and below) all hit one mesh within 1 mm + 1e-5 x
/// range of the plane of the centre's triangle, and gives such a beam's axis ray and hit
/// in axis_rays[i] and axis_hits[i] (the others' are left as they are). Beams on the image
/// border are never planar. Each axis is traced once per thread and (view, row) run of
/// consecutive calls, in a packet of the 16 columns of its row from a multiple of 16 (or
/// alone without `packets`), so the results depend on neither the order of the calls nor
/// the threads. Kept axes are told apart by (sensor id, caster address, view, pose flown,
/// packets): a sensor must not trace one view through a new caster built where an old one
/// was destroyed (sim::Generator builds its caster and sensor together).
void markPlanar(const AxisSource& src, const RayCaster& caster, const SensorView& v, std::int64_t y, std::int64_t x0,
                std::size_t n, bool packets, std::span<std::uint8_t> planar, std::span<Ray> axis_rays,
                std::span<Hit> axis_hits);

/// Bytes of the per-thread axis cache for an image `xres` pixels wide.
std::size_t axisCacheBytes(int xres);

}  // namespace sim::sensor_model
