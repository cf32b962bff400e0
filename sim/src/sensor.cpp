// sim/src/sensor.cpp: the seam between the generator and the ray caster (see
// sim/sensor.hpp). The ideal sensor traces one ray per pixel and keeps its first hit, as
// paper §III-B does; every other model goes through one path that makes a beam's
// sub-rays, traces them as 16-ray packets, and turns the echoes into returns with the
// models of sensor_*.cpp. Embree itself is only called inside RayCaster.
#include <sim/sensor.hpp>

#include "sensor_axes.hpp"
#include "sensor_models.hpp"

#include <core/error.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>
#include <string>

namespace sim {
namespace {

constexpr double kSpeedOfLight_m_per_s = 299792458.0;
constexpr double kRadToDeg = 180.0 / std::numbers::pi;
constexpr int kMaxReturns = 15;           // LAS 1.4 point formats 6-10 hold return numbers 1..15
constexpr std::size_t kChunkRays = 1024;  // rays traced per call into the RayCaster

bool footprintOn(const SensorOptions& o) { return o.beam_divergence_mrad > 0.0; }
bool intensityOn(const SensorOptions& o) {
    return o.intensity || o.min_intensity > 0.0 || footprintOn(o) || o.returns == ReturnMode::Strongest;
}

void checkRange(double v, double lo, double hi, const char* parameter, const char* option, const char* unit) {
    if (!(std::isfinite(v) && v >= lo && v <= hi))
        throw core::Error(std::string("sensor: ") + parameter + " (" + option + ") = " + core::shownNumber(v) +
                          ": allowed [" + core::shownNumber(lo) + ", " + core::shownNumber(hi) + "]" + unit);
}

// The LAS scan angle of a sensor-frame direction: its angle from the optical axis, signed
// by its side across the image.
float scanAngle_deg(const glm::dvec3& d) {
    return float(std::copysign(std::acos(std::clamp(d.z, -1.0, 1.0)) * kRadToDeg, d.x));
}

// Images up to this many pixels keep their axes' directions and scan angles in a table
// (28 bytes a pixel, less than the generator's own buffers for one view): every view has
// the same, the planar test traces every axis, and the axis places most returns.
constexpr std::size_t kAxisTablePixels = std::size_t(1) << 18;

// Per-thread buffers of one trace call (reused across calls).
struct Scratch {
    std::vector<Ray> rays;           // the ideal path: one per pixel; else the sub-rays of the
    std::vector<Hit> hits;           // beams that trace them, beam after beam
    std::vector<glm::dvec3> dirs;    // sensor frame, per sub-ray of `rays`
    std::vector<std::size_t> first;  // per beam: its first sub-ray in `rays`
    std::vector<std::uint8_t> planar;
    std::vector<Ray> axis_rays;  // per planar beam: its axis ray and hit
    std::vector<Hit> axis_hits;
    std::vector<sensor_model::Echo> echoes;
    std::vector<double> cos_incidence;  // per sub-ray of the beam being turned into returns
};
thread_local Scratch t_scratch;

// Makes `v` hold at least n elements; buffers only grow, as resizing down and up would
// construct the elements anew on every call.
template <class T>
void growTo(std::vector<T>& v, std::size_t n) {
    if (v.size() < n) v.resize(n);
}

}  // namespace

std::string_view returnModeName(ReturnMode m) {
    switch (m) {
        case ReturnMode::First: return "first";
        case ReturnMode::Last: return "last";
        case ReturnMode::Strongest: return "strongest";
        case ReturnMode::All: return "all";
    }
    return "first";
}

ReturnMode parseReturnMode(std::string_view text, std::string_view parameter) {
    for (ReturnMode m : {ReturnMode::First, ReturnMode::Last, ReturnMode::Strongest, ReturnMode::All})
        if (text == returnModeName(m)) return m;
    throw core::Error(std::string(parameter) + ": '" + std::string(text.substr(0, 40)) +
                      "' is not one of first, last, strongest, all");
}

void validate(const SensorOptions& o) {
    checkRange(o.range_noise_m, 0.0, 100.0, "range_noise_m", "--range-noise-m", " metres");
    checkRange(o.pose_noise_m, 0.0, 100.0, "pose_noise_m", "--pose-noise-m", " metres");
    checkRange(o.attitude_noise_deg, 0.0, 10.0, "attitude_noise_deg", "--attitude-noise-deg", " degrees");
    checkRange(o.pose_bias_m, 0.0, 100.0, "pose_bias_m", "--pose-bias-m", " metres");
    checkRange(o.attitude_bias_deg, 0.0, 10.0, "attitude_bias_deg", "--attitude-bias-deg", " degrees");
    checkRange(o.max_range_m, 0.0, 1e7, "max_range_m", "--max-range-m", " metres, 0 = no limit");
    checkRange(o.intensity_reference_range_m, 1e-3, 1e7, "intensity_reference_range_m", "--intensity-reference-range-m",
               " metres");
    checkRange(o.min_intensity, 0.0, 65535.0, "min_intensity", "--min-intensity", " (LAS intensity counts)");
    checkRange(o.beam_divergence_mrad, 0.0, 100.0, "beam_divergence_mrad", "--beam-divergence-mrad",
               " mrad, 0 = a thin beam");
    checkRange(o.beam_divergence_y_mrad, 0.0, 100.0, "beam_divergence_y_mrad", "--beam-divergence-y-mrad",
               " mrad, 0 = circular");
    if (o.footprint_quality < 1 || o.footprint_quality > 5)
        throw core::Error("sensor: footprint_quality (--footprint-quality) = " + std::to_string(o.footprint_quality) +
                          ": allowed [1, 5]");
    if (o.max_returns < 1 || o.max_returns > kMaxReturns)
        throw core::Error("sensor: max_returns (--max-returns) = " + std::to_string(o.max_returns) + ": allowed [1, " +
                          std::to_string(kMaxReturns) + "]");
    checkRange(o.pulse_ns, 0.01, 1000.0, "pulse_ns", "--pulse-ns", " ns");
    checkRange(o.range_resolution_m, 0.0, 1000.0, "range_resolution_m", "--range-resolution-m",
               " metres, 0 = c * pulse / 2");
}

bool isIdeal(const SensorOptions& o) {
    return o.range_noise_m == 0.0 && o.pose_noise_m == 0.0 && o.attitude_noise_deg == 0.0 && o.pose_bias_m == 0.0 &&
           o.attitude_bias_deg == 0.0 && o.max_range_m == 0.0 && !intensityOn(o) && !footprintOn(o) &&
           o.returns == ReturnMode::First;
}

struct Sensor::State {
    SensorOptions o;
    OrbitOptions orbit;
    std::uint64_t seed = 1;
    bool ideal = true;
    bool intensity = false;
    std::vector<SubRay> pattern;
    std::vector<glm::dvec2> tans;     // per sub-ray, tan of its offsets
    std::vector<double> reflectance;  // per mesh
    double resolution_m = 0.0;
    double min_power = 0.0;
    std::size_t slots = 1;
    float t_far = std::numeric_limits<float>::infinity();
    std::uint64_t id = sensor_model::newSensorId();  // keys the per-thread axis cache
    std::vector<glm::dvec3> axis_direction;          // per pixel (row-major), pixelDirection; empty: computed
    std::vector<float> axis_scan_angle_deg;          // per pixel, of its axis; empty: computed
};

Sensor::Sensor(const SensorOptions& o, const OrbitOptions& orbit, const core::Scene& scene, std::uint64_t seed)
    : state_(std::make_unique<State>()) {
    validate(o);
    State& s = *state_;
    s.o = o;
    s.orbit = orbit;
    s.seed = seed;
    s.ideal = isIdeal(o);
    s.intensity = intensityOn(o);
    s.pattern = footprintPattern(o);
    for (const SubRay& r : s.pattern) s.tans.emplace_back(std::tan(r.dx_rad), std::tan(r.dy_rad));
    for (const core::Mesh& m : scene.meshes) s.reflectance.push_back(m.reflectance);
    s.resolution_m =
        o.range_resolution_m > 0.0 ? o.range_resolution_m : 0.5 * kSpeedOfLight_m_per_s * o.pulse_ns * 1e-9;
    s.min_power = o.min_intensity / 65535.0;
    s.slots = o.returns == ReturnMode::All && footprintOn(o) ? std::size_t(o.max_returns) : 1;
    if (o.max_range_m > 0.0) s.t_far = float(o.max_range_m);
    const std::size_t pixels = std::size_t(orbit.xres) * std::size_t(orbit.yres);
    if (!s.ideal && pixels <= kAxisTablePixels) {
        s.axis_direction.reserve(pixels);
        s.axis_scan_angle_deg.reserve(pixels);
        for (int y = 0; y < orbit.yres; ++y)
            for (int x = 0; x < orbit.xres; ++x) {
                s.axis_direction.push_back(pixelDirection(orbit, double(x), double(y)));
                s.axis_scan_angle_deg.push_back(scanAngle_deg(s.axis_direction.back()));
            }
    }
}

Sensor::~Sensor() = default;

const SensorOptions& Sensor::options() const { return state_->o; }
bool Sensor::ideal() const { return state_->ideal; }
std::size_t Sensor::slotsPerPixel() const { return state_->slots; }
std::size_t Sensor::raysPerPixel() const { return state_->pattern.size(); }

std::size_t Sensor::scratchBytes() const {
    const std::size_t per = state_->pattern.size();
    const std::size_t rays = per == 1 ? kChunkRays : std::max<std::size_t>(1, kChunkRays / per) * per;
    const std::size_t pixels = per == 1 ? kChunkRays : rays / per;
    return rays * (sizeof(Ray) + sizeof(Hit) + sizeof(glm::dvec3) + sizeof(sensor_model::Echo) + sizeof(double)) +
           pixels * (sizeof(std::size_t) + 1 + sizeof(Ray) + sizeof(Hit)) +
           (per > 1 && !state_->o.footprint_exact ? sensor_model::axisCacheBytes(state_->orbit.xres) : 0);
}

std::size_t Sensor::tableBytes() const {
    return state_->axis_direction.capacity() * sizeof(glm::dvec3) +
           state_->axis_scan_angle_deg.capacity() * sizeof(float);
}

core::CloudFields Sensor::fields() const {
    const State& s = *state_;
    core::CloudFields f;
    if (s.ideal) return f;
    f.incidence = true;
    f.scan_angle = true;
    f.intensity = s.intensity;
    f.returns = footprintOn(s.o) || s.o.returns != ReturnMode::First;
    return f;
}

SensorView Sensor::view(int index, const core::Pose& nominal) const {
    return SensorView{index, nominal, sensor_model::actualPose(state_->o, state_->seed, index, nominal)};
}

namespace {

// The ideal sensor over one chunk of pixels (paper §III-B): one ray per pixel centre from
// the pose, its first hit, into the pixel's one slot.
void traceIdeal(const Sensor::State& s, const RayCaster& caster, const SensorView& v, std::span<const glm::dvec3> dirs,
                std::span<core::CloudPoint> slots, bool packets, Scratch& sc) {
    const std::size_t pixels = dirs.size();
    const glm::vec3 origin(v.actual.translation);
    growTo(sc.rays, pixels);
    growTo(sc.hits, pixels);
    const std::span<Ray> rays(sc.rays.data(), pixels);
    const std::span<Hit> hits(sc.hits.data(), pixels);
    for (std::size_t i = 0; i < pixels; ++i) rays[i] = Ray{origin, glm::vec3(v.actual.rotation * dirs[i]), s.t_far};
    if (packets)
        caster.intersect16(rays, hits);
    else
        caster.intersect(rays, hits);
    const glm::dvec3 origin_d(origin);
    for (std::size_t i = 0; i < pixels; ++i) {
        core::CloudPoint& cp = slots[i];
        const Hit& h = hits[i];
        if (!h.hit()) {
            cp.range_m = kNoReturn;
            continue;
        }
        cp.position = glm::vec3(origin_d + double(h.t) * glm::dvec3(rays[i].direction));
        cp.range_m = h.t;
        cp.view = std::uint16_t(v.view);
        cp.label = h.role;
        cp.rgb = 0;
    }
}

// Every other model, over one chunk of pixels from `first_pixel`: the beam's sub-rays
// from the pose actually flown, those of beams on one plane (adaptive) replaced by their
// axis (sc.planar, sc.axis_rays, sc.axis_hits), traced one beam after the other (16-ray
// packets across beams) into sc.rays, sc.hits and their directions sc.dirs, beam i's
// from sc.first[i].
void castSubRays(const Sensor::State& s, const RayCaster& caster, const SensorView& v, std::uint64_t first_pixel,
                 std::span<const glm::dvec3> dirs, bool packets, Scratch& sc) {
    const std::size_t per = s.pattern.size(), pixels = dirs.size();
    const bool adaptive = per > 1 && !s.o.footprint_exact;
    sc.planar.assign(pixels, 0);
    growTo(sc.axis_rays, pixels);
    growTo(sc.axis_hits, pixels);
    if (adaptive) {
        const std::uint64_t xres = std::uint64_t(s.orbit.xres);
        sensor_model::markPlanar(sensor_model::AxisSource{s.id, &s.orbit, s.t_far, s.axis_direction}, caster, v,
                                 std::int64_t(first_pixel / xres), std::int64_t(first_pixel % xres), pixels, packets,
                                 sc.planar, sc.axis_rays, sc.axis_hits);
    }
    std::size_t traced = 0;
    growTo(sc.first, pixels);
    for (std::size_t i = 0; i < pixels; ++i) {
        sc.first[i] = traced;
        traced += sc.planar[i] ? 0 : per;
    }
    growTo(sc.rays, traced);
    growTo(sc.hits, traced);
    growTo(sc.dirs, traced);
    // (Locals, not members: the stores below could alias them and force reloads.)
    Ray* const sub_rays = sc.rays.data();
    glm::dvec3* const sub_dirs = sc.dirs.data();
    const glm::dvec2* const tans = s.tans.data();
    const glm::dmat3 rotation = v.actual.rotation;
    const glm::vec3 origin(v.actual.translation);
    const float t_far = s.t_far;
    for (std::size_t i = 0; i < pixels; ++i) {
        if (sc.planar[i]) continue;
        const BeamFrame frame = per == 1 ? BeamFrame{dirs[i], {}, {}} : beamFrame(dirs[i]);
        for (std::size_t k = 0, j = sc.first[i]; k < per; ++k, ++j) {
            const glm::dvec3 d = subRayDirection(frame, tans[k].x, tans[k].y);
            sub_dirs[j] = d;
            Ray& ray = sub_rays[j];
            ray.origin = origin;
            ray.direction = glm::vec3(rotation * d);
            ray.t_far = t_far;
        }
    }
    const std::span<const Ray> sub_ray_span(sc.rays.data(), traced);
    const std::span<Hit> sub_hit_span(sc.hits.data(), traced);
    if (packets)
        caster.intersect16(sub_ray_span, sub_hit_span);
    else
        caster.intersect(sub_ray_span, sub_hit_span);
}

// The echoes castSubRays traced for one chunk of pixels from `first_pixel`, turned into
// returns (sensor_returns.cpp) and placed with the pose the drone believes it flew, into
// each pixel's slots; a slot without a return gets range_m = kNoReturn. `same_pose`:
// without a pose error the rays' own directions place the points.
void placeReturns(const Sensor::State& s, const SensorView& v, std::uint64_t first_pixel,
                  std::span<const glm::dvec3> dirs, std::span<core::CloudPoint> slots, bool same_pose, Scratch& sc) {
    const std::size_t per = s.pattern.size(), pixels = dirs.size();
    const bool noisy = s.o.range_noise_m > 0.0;
    const glm::dvec3 origin_n(glm::vec3(v.nominal.translation));
    sensor_model::Return out[kMaxReturns];
    growTo(sc.echoes, per);
    growTo(sc.cos_incidence, per);
    sensor_model::Echo* const echoes = sc.echoes.data();
    double* const cos_incidence = sc.cos_incidence.data();
    const SubRay* const pattern = s.pattern.data();
    const double* const reflectance = s.reflectance.data();
    const double reference_range_m = s.o.intensity_reference_range_m;
    const bool intensity = s.intensity;
    for (std::size_t i = 0; i < pixels; ++i) {
        const bool planar = sc.planar[i];
        const std::size_t used = planar ? 1 : per;  // a planar beam: its axis, all its power
        const Ray* rays = planar ? &sc.axis_rays[i] : sc.rays.data() + sc.first[i];
        const Hit* hits = planar ? &sc.axis_hits[i] : sc.hits.data() + sc.first[i];
        const glm::dvec3* ds = planar ? &dirs[i] : sc.dirs.data() + sc.first[i];
        std::size_t echo_count = 0;
        for (std::size_t k = 0; k < used; ++k) {
            const Hit& h = hits[k];
            if (!h.hit()) continue;
            double power = planar ? 1.0 : pattern[k].weight;
            if (intensity) {
                const double c = sensor_model::cosIncidence(glm::dvec3(rays[k].direction), glm::dvec3(h.normal));
                cos_incidence[k] = c;
                power *= sensor_model::echoPower(reflectance[std::size_t(h.mesh)], c, double(h.t), reference_range_m);
            }
            echoes[echo_count++] = sensor_model::Echo{h.t, power, std::uint32_t(k)};
        }
        int detected = 0, first_rank = 1;
        const std::size_t n =
            sensor_model::formReturns(std::span(echoes, echo_count), s.resolution_m, s.min_power, s.o.returns,
                                      s.o.max_returns, std::span(out, s.slots), &detected, &first_rank);
        core::CloudPoint* px = &slots[i * s.slots];
        const std::uint64_t pixel = first_pixel + i;
        for (std::size_t r = 0; r < n; ++r) {
            const sensor_model::Echo& e = echoes[out[r].strongest];
            const std::size_t k = e.sub;
            const Hit& h = hits[k];
            const glm::dvec3& d = ds[k];
            const int rank = std::min(kMaxReturns, first_rank + int(r));
            const double t =
                noisy ? std::max(0.0, double(e.t) + sensor_model::rangeError_m(s.o, s.seed, v.view, pixel, rank))
                      : double(e.t);
            const glm::dvec3 dir_n =
                same_pose ? glm::dvec3(rays[k].direction) : glm::dvec3(glm::vec3(v.nominal.rotation * d));
            const double cos_i = s.intensity
                                     ? cos_incidence[k]
                                     : sensor_model::cosIncidence(glm::dvec3(rays[k].direction), glm::dvec3(h.normal));
            core::CloudPoint& cp = px[r];
            cp.position = glm::vec3(origin_n + t * dir_n);
            cp.range_m = float(t);
            cp.view = std::uint16_t(v.view);
            cp.label = h.role;
            cp.rgb = 0;
            cp.intensity = s.intensity ? sensor_model::intensityCounts(out[r].power) : 0;
            cp.incidence_deg = float(std::acos(cos_i) * kRadToDeg);
            // Sub-ray 0 is the axis (of the caller's pixelDirection, which the table holds).
            cp.scan_angle_deg =
                k == 0 && !s.axis_scan_angle_deg.empty() ? s.axis_scan_angle_deg[pixel] : scanAngle_deg(d);
            cp.return_number = std::uint8_t(rank);
            cp.returns = std::uint8_t(std::clamp(detected, rank, kMaxReturns));
        }
        for (std::size_t r = n; r < s.slots; ++r) px[r].range_m = kNoReturn;
    }
}

}  // namespace

void Sensor::trace(const RayCaster& caster, const SensorView& v, std::uint64_t first_pixel,
                   std::span<const glm::dvec3> dirs, std::span<core::CloudPoint> slots, bool packets) const {
    const State& s = *state_;
    const std::size_t per = s.pattern.size();
    Scratch& sc = t_scratch;
    // Chunks of whole pixels; with one ray per pixel a multiple of 16, so that packets start
    // at the same pixels however the caller splits its runs into chunks.
    const std::size_t chunk_pixels = per == 1 ? kChunkRays : std::max<std::size_t>(1, kChunkRays / per);
    // Without a pose error the rays' own directions place the points.
    const bool same_pose = std::memcmp(&v.nominal.rotation, &v.actual.rotation, sizeof v.actual.rotation) == 0;
    for (std::size_t c0 = 0; c0 < dirs.size(); c0 += chunk_pixels) {
        const std::size_t pixels = std::min(chunk_pixels, dirs.size() - c0);
        const std::span<const glm::dvec3> chunk_dirs = dirs.subspan(c0, pixels);
        const std::span<core::CloudPoint> chunk_slots = slots.subspan(c0 * s.slots, pixels * s.slots);
        if (s.ideal) {
            traceIdeal(s, caster, v, chunk_dirs, chunk_slots, packets, sc);
            continue;
        }
        castSubRays(s, caster, v, first_pixel + c0, chunk_dirs, packets, sc);
        placeReturns(s, v, first_pixel + c0, chunk_dirs, chunk_slots, same_pose, sc);
    }
}

}  // namespace sim
