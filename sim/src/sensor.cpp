// sim/src/sensor.cpp: the seam between the generator and the ray caster (see
// sim/sensor.hpp). The ideal sensor traces one ray per pixel and keeps its first hit, as
// paper §III-B does; every other model goes through one path that makes a beam's
// sub-rays, traces them as 16-ray packets, and turns the echoes into returns with the
// models of sensor_*.cpp. Embree itself is only called inside RayCaster.
#include <sim/sensor.hpp>

#include "sensor_models.hpp"

#include <engine/error.hpp>

#include <algorithm>
#include <cmath>
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
        throw engine::Error(std::string("sensor: ") + parameter + " (" + option + ") = " + engine::shownNumber(v) +
                            ": allowed [" + engine::shownNumber(lo) + ", " + engine::shownNumber(hi) + "]" + unit);
}

// Per-thread buffers of one trace call (reused across calls).
struct Scratch {
    std::vector<Ray> rays;
    std::vector<Hit> hits;
    std::vector<glm::dvec3> dirs;  // sensor frame, per ray
    std::vector<sensor_model::Echo> echoes;
    std::vector<Ray> nb_rays, todo_rays;   // neighbourhood axes; sub-rays of non-planar beams
    std::vector<Hit> nb_hits, todo_hits;
    std::vector<std::uint8_t> nb_valid, planar;
};
thread_local Scratch t_scratch;

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
    throw engine::Error(std::string(parameter) + ": '" + std::string(text.substr(0, 40)) +
                        "' is not one of first, last, strongest, all");
}

void validate(const SensorOptions& o) {
    checkRange(o.range_noise_m, 0.0, 100.0, "range_noise_m", "--range-noise-m", " metres");
    checkRange(o.pose_noise_m, 0.0, 100.0, "pose_noise_m", "--pose-noise-m", " metres");
    checkRange(o.attitude_noise_deg, 0.0, 10.0, "attitude_noise_deg", "--attitude-noise-deg", " degrees");
    checkRange(o.pose_bias_m, 0.0, 100.0, "pose_bias_m", "--pose-bias-m", " metres");
    checkRange(o.attitude_bias_deg, 0.0, 10.0, "attitude_bias_deg", "--attitude-bias-deg", " degrees");
    checkRange(o.max_range_m, 0.0, 1e7, "max_range_m", "--max-range-m", " metres, 0 = no limit");
    checkRange(o.intensity_reference_range_m, 1e-3, 1e7, "intensity_reference_range_m",
               "--intensity-reference-range-m", " metres");
    checkRange(o.min_intensity, 0.0, 65535.0, "min_intensity", "--min-intensity", " (LAS intensity counts)");
    checkRange(o.beam_divergence_mrad, 0.0, 100.0, "beam_divergence_mrad", "--beam-divergence-mrad",
               " mrad, 0 = a thin beam");
    checkRange(o.beam_divergence_y_mrad, 0.0, 100.0, "beam_divergence_y_mrad", "--beam-divergence-y-mrad",
               " mrad, 0 = circular");
    if (o.footprint_quality < 1 || o.footprint_quality > 5)
        throw engine::Error("sensor: footprint_quality (--footprint-quality) = " +
                            std::to_string(o.footprint_quality) + ": allowed [1, 5]");
    if (o.max_returns < 1 || o.max_returns > kMaxReturns)
        throw engine::Error("sensor: max_returns (--max-returns) = " + std::to_string(o.max_returns) +
                            ": allowed [1, " + std::to_string(kMaxReturns) + "]");
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
};

Sensor::Sensor(const SensorOptions& o, const OrbitOptions& orbit, const engine::Scene& scene, std::uint64_t seed)
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
    for (const engine::Mesh& m : scene.meshes) s.reflectance.push_back(m.reflectance);
    s.resolution_m = o.range_resolution_m > 0.0 ? o.range_resolution_m : 0.5 * kSpeedOfLight_m_per_s * o.pulse_ns * 1e-9;
    s.min_power = o.min_intensity / 65535.0;
    s.slots = o.returns == ReturnMode::All && footprintOn(o) ? std::size_t(o.max_returns) : 1;
    if (o.max_range_m > 0.0) s.t_far = float(o.max_range_m);
}

Sensor::~Sensor() = default;

namespace {

// For the beams of `dirs` (consecutive pixels of one row from `first_pixel`): traces the
// axes of their 3x3 neighbourhoods (the row and those above and below, one pixel past each
// end) and sets sc.planar[i] where all nine hit one mesh within 1 mm + 1e-5 x range of
// the plane of the centre's triangle. A beam's footprint lies within its pixel's cell, which the
// neighbours' axes enclose, so such a beam sees that plane alone (a feature narrower than the
// pixel spacing between the axes can be missed: footprint_exact traces every sub-ray).
// Planar beams get their axis ray and hit at rays/hits[i * per].
void markPlanar(const Sensor::State& s, const RayCaster& caster, const SensorView& v, std::uint64_t first_pixel,
                std::span<const glm::dvec3> dirs, bool packets, std::span<Ray> rays, std::span<Hit> hits,
                Scratch& sc) {
    const std::size_t per = s.pattern.size();
    const std::int64_t xres = s.orbit.xres, yres = s.orbit.yres;
    const std::int64_t y = std::int64_t(first_pixel) / xres, x0 = std::int64_t(first_pixel) % xres;
    const std::size_t n = dirs.size(), w = n + 2;
    const glm::vec3 origin(v.actual.translation);
    sc.nb_rays.resize(3 * w);
    sc.nb_hits.resize(3 * w);
    sc.nb_valid.assign(3 * w, 0);
    for (std::size_t r = 0; r < 3; ++r)
        for (std::size_t c = 0; c < w; ++c) {
            const std::int64_t row = y - 1 + std::int64_t(r), col = x0 - 1 + std::int64_t(c);
            const bool valid = row >= 0 && row < yres && col >= 0 && col < xres;
            const glm::dvec3 d = r == 1 && c >= 1 && c <= n ? dirs[c - 1]
                                 : valid ? pixelDirection(s.orbit, double(col), double(row))
                                         : glm::dvec3(0.0, 0.0, 1.0);
            sc.nb_valid[r * w + c] = valid;
            sc.nb_rays[r * w + c] = Ray{origin, glm::vec3(v.actual.rotation * d), s.t_far};
        }
    if (packets) caster.intersect16(sc.nb_rays, sc.nb_hits);
    else caster.intersect(sc.nb_rays, sc.nb_hits);
    const glm::dvec3 o(origin);
    const auto point = [&](std::size_t k) {
        return o + double(sc.nb_hits[k].t) * glm::dvec3(sc.nb_rays[k].direction);
    };
    for (std::size_t i = 0; i < n; ++i) {
        const std::size_t centre = w + i + 1;
        const Hit& hc = sc.nb_hits[centre];
        if (!hc.hit() || !(glm::length(hc.normal) > 0.0f)) continue;
        const glm::dvec3 normal = glm::normalize(glm::dvec3(hc.normal));
        const glm::dvec3 pc = point(centre);
        const double tolerance_m = 1e-3 + 1e-5 * double(hc.t);
        bool planar = true;
        for (std::size_t r = 0; r < 3 && planar; ++r)
            for (std::size_t c = i; c < i + 3 && planar; ++c) {
                const std::size_t k = r * w + c;
                const Hit& h = sc.nb_hits[k];
                planar = sc.nb_valid[k] && h.hit() && h.mesh == hc.mesh &&
                         std::abs(glm::dot(normal, point(k) - pc)) <= tolerance_m;
            }
        if (!planar) continue;
        sc.planar[i] = 1;
        rays[i * per] = sc.nb_rays[centre];
        hits[i * per] = hc;
    }
}

}  // namespace

const SensorOptions& Sensor::options() const { return state_->o; }
bool Sensor::ideal() const { return state_->ideal; }
std::size_t Sensor::slotsPerPixel() const { return state_->slots; }
std::size_t Sensor::raysPerPixel() const { return state_->pattern.size(); }

std::size_t Sensor::scratchBytes() const {
    const std::size_t per = state_->pattern.size();
    const std::size_t rays = per == 1 ? kChunkRays : std::max<std::size_t>(1, kChunkRays / per) * per;
    return rays * (sizeof(Ray) + sizeof(Hit) + sizeof(glm::dvec3) + sizeof(sensor_model::Echo));
}

engine::CloudFields Sensor::fields() const {
    const State& s = *state_;
    engine::CloudFields f;
    if (s.ideal) return f;
    f.incidence = true;
    f.scan_angle = true;
    f.intensity = s.intensity;
    f.returns = footprintOn(s.o) || s.o.returns != ReturnMode::First;
    return f;
}

SensorView Sensor::view(int index, const engine::Pose& nominal) const {
    return SensorView{index, nominal, sensor_model::actualPose(state_->o, state_->seed, index, nominal)};
}

void Sensor::trace(const RayCaster& caster, const SensorView& v, std::uint64_t first_pixel,
                   std::span<const glm::dvec3> dirs, std::span<engine::CloudPoint> slots, bool packets) const {
    const State& s = *state_;
    const std::size_t per = s.pattern.size();
    const glm::vec3 origin(v.actual.translation);
    Scratch& sc = t_scratch;
    // Chunks of whole pixels; with one ray per pixel a multiple of 16, so that packets start
    // at the same pixels however the caller splits its runs into chunks.
    const std::size_t chunk_pixels = per == 1 ? kChunkRays : std::max<std::size_t>(1, kChunkRays / per);
    sc.rays.resize(chunk_pixels * per);
    sc.hits.resize(chunk_pixels * per);
    for (std::size_t c0 = 0; c0 < dirs.size(); c0 += chunk_pixels) {
        const std::size_t pixels = std::min(chunk_pixels, dirs.size() - c0);
        const std::span<Ray> rays(sc.rays.data(), pixels * per);
        const std::span<Hit> hits(sc.hits.data(), pixels * per);

        if (s.ideal) {
            // Paper §III-B: one ray per pixel centre from the pose, its first hit.
            for (std::size_t i = 0; i < pixels; ++i)
                rays[i] = Ray{origin, glm::vec3(v.actual.rotation * dirs[c0 + i]), s.t_far};
            if (packets) caster.intersect16(rays, hits);
            else caster.intersect(rays, hits);
            const glm::dvec3 origin_d(origin);
            for (std::size_t i = 0; i < pixels; ++i) {
                engine::CloudPoint& cp = slots[c0 + i];
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
            continue;
        }

        // Every other model: the beam's sub-rays from the pose actually flown ...
        sc.dirs.resize(pixels * per);
        const bool adaptive = per > 1 && !s.o.footprint_exact;
        sc.planar.assign(pixels, 0);
        if (adaptive) markPlanar(s, caster, v, first_pixel + c0, dirs.subspan(c0, pixels), packets, rays, hits, sc);
        sc.todo_rays.clear();
        for (std::size_t i = 0; i < pixels; ++i) {
            if (sc.planar[i]) {
                sc.dirs[i * per] = dirs[c0 + i];
                continue;
            }
            const BeamFrame frame = per == 1 ? BeamFrame{dirs[c0 + i], {}, {}} : beamFrame(dirs[c0 + i]);
            for (std::size_t k = 0; k < per; ++k) {
                const glm::dvec3 d = subRayDirection(frame, s.tans[k].x, s.tans[k].y);
                sc.dirs[i * per + k] = d;
                rays[i * per + k] = Ray{origin, glm::vec3(v.actual.rotation * d), s.t_far};
                if (adaptive) sc.todo_rays.push_back(rays[i * per + k]);
            }
        }
        if (!adaptive) {
            if (packets) caster.intersect16(rays, hits);
            else caster.intersect(rays, hits);
        } else {
            // Only the beams that are not on one plane, their sub-rays one after the other.
            sc.todo_hits.resize(sc.todo_rays.size());
            if (packets) caster.intersect16(sc.todo_rays, sc.todo_hits);
            else caster.intersect(sc.todo_rays, sc.todo_hits);
            std::size_t next = 0;
            for (std::size_t i = 0; i < pixels; ++i)
                if (!sc.planar[i])
                    for (std::size_t k = 0; k < per; ++k) hits[i * per + k] = sc.todo_hits[next++];
        }
        // ... and the returns placed with the pose the drone believes it flew.
        const glm::dvec3 origin_n(glm::vec3(v.nominal.translation));
        sensor_model::Return out[kMaxReturns];
        for (std::size_t i = 0; i < pixels; ++i) {
            sc.echoes.clear();
            const std::size_t used = sc.planar[i] ? 1 : per;  // a planar beam: its axis, all its power
            for (std::size_t k = 0; k < used; ++k) {
                const Hit& h = hits[i * per + k];
                if (!h.hit()) continue;
                double power = sc.planar[i] ? 1.0 : s.pattern[k].weight;
                if (s.intensity)
                    power *= sensor_model::echoPower(
                        s.reflectance[std::size_t(h.mesh)],
                        sensor_model::cosIncidence(glm::dvec3(rays[i * per + k].direction), glm::dvec3(h.normal)),
                        double(h.t), s.o.intensity_reference_range_m);
                sc.echoes.push_back(sensor_model::Echo{h.t, power, std::uint32_t(k)});
            }
            int detected = 0, first_rank = 1;
            const std::size_t n = sensor_model::formReturns(sc.echoes, s.resolution_m, s.min_power, s.o.returns,
                                                            s.o.max_returns, std::span(out, s.slots), &detected,
                                                            &first_rank);
            engine::CloudPoint* px = &slots[(c0 + i) * s.slots];
            const std::uint64_t pixel = first_pixel + c0 + i;
            for (std::size_t r = 0; r < n; ++r) {
                const sensor_model::Echo& e = sc.echoes[out[r].strongest];
                const std::size_t ray = i * per + e.sub;
                const Hit& h = hits[ray];
                const glm::dvec3& d = sc.dirs[ray];
                const int rank = std::min(kMaxReturns, first_rank + int(r));
                const double t = std::max(0.0, double(e.t) + sensor_model::rangeError_m(s.o, s.seed, v.view, pixel, rank));
                const glm::dvec3 dir_n(glm::vec3(v.nominal.rotation * d));
                engine::CloudPoint& cp = px[r];
                cp.position = glm::vec3(origin_n + t * dir_n);
                cp.range_m = float(t);
                cp.view = std::uint16_t(v.view);
                cp.label = h.role;
                cp.rgb = 0;
                cp.intensity = s.intensity ? sensor_model::intensityCounts(out[r].power) : 0;
                cp.incidence_deg = float(
                    std::acos(sensor_model::cosIncidence(glm::dvec3(rays[ray].direction), glm::dvec3(h.normal))) *
                    kRadToDeg);
                cp.scan_angle_deg = float(std::copysign(std::acos(std::clamp(d.z, -1.0, 1.0)) * kRadToDeg, d.x));
                cp.return_number = std::uint8_t(rank);
                cp.returns = std::uint8_t(std::clamp(detected, rank, kMaxReturns));
            }
            for (std::size_t r = n; r < s.slots; ++r) px[r].range_m = kNoReturn;
        }
    }
}

}  // namespace sim
