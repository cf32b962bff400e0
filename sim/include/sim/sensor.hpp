// sim/sensor.hpp: the Ladar sensor between the generator and the ray caster. The generator
// hands it the pixels of a view; the sensor makes their rays (one per pixel, or a beam
// footprint of sub-rays), has the RayCaster trace them, and turns the hits into returns.
// The ideal sensor (the default, paper §III-B) gives one exact first hit per pixel from a
// perfectly known pose; the models of docs/sensor.md (range noise, GNSS/INS pose error,
// maximum range, intensity, beam divergence with several returns) are each off by default.
#pragma once
#include <core/frames.hpp>
#include <core/point_cloud.hpp>
#include <core/scene.hpp>
#include <sim/orbit.hpp>
#include <sim/raycaster.hpp>

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace sim {

/// Which of the returns a pulse gives are kept.
enum class ReturnMode { First, Last, Strongest, All };

/// "first", "last", "strongest", "all".
std::string_view returnModeName(ReturnMode m);
/// Throws core::Error("<parameter>: '<text>' is not one of first, last, strongest, all").
ReturnMode parseReturnMode(std::string_view text, std::string_view parameter);

/// Every sensor model's parameters; the defaults are the ideal sensor (every model off).
struct SensorOptions {
    double range_noise_m = 0.0;                  // sigma of the Gaussian range error along the beam
    double pose_noise_m = 0.0;                   // sigma per axis of the position error, drawn per view
    double attitude_noise_deg = 0.0;             // sigma per axis (roll, pitch, yaw) of the attitude error, per view
    double pose_bias_m = 0.0;                    // sigma per axis of a position error drawn once per flight
    double attitude_bias_deg = 0.0;              // sigma per axis of an attitude error drawn once per flight
    double max_range_m = 0.0;                    // echoes farther than this are lost; 0 = no limit
    bool intensity = false;                      // fill intensity and incidence (the lidar equation)
    double intensity_reference_range_m = 300.0;  // R0: reflectance 1, normal incidence, R0 -> 65535
    double min_intensity = 0.0;                  // echoes weaker than this (0..65535) are lost; > 0 turns intensity on
    double beam_divergence_mrad = 0.0;           // full angle at 1/e^2 across the image (x); 0 = a thin beam
    double beam_divergence_y_mrad = 0.0;         // down the image (y); 0 = the same as x (a circular footprint)
    int footprint_quality = 3;                   // q: the footprint is sampled by 1 + sum_{k<q} int(2 pi k) sub-rays
    /// Trace every sub-ray of every beam. Off: a beam whose 3x3 neighbourhood of pixel axes
    /// hits one plane of one mesh is not sub-sampled (its footprint lies on that plane: one
    /// return, on its axis, with the beam's whole power); only the others are.
    bool footprint_exact = false;
    ReturnMode returns = ReturnMode::First;
    int max_returns = 5;              // returns kept per pulse at most with ReturnMode::All (1..15)
    double pulse_ns = 4.0;            // pulse width; sets the default range resolution c*pulse/2
    double range_resolution_m = 0.0;  // echoes closer than this merge into one return; 0 = c*pulse/2
};

/// Throws core::Error("sensor: <parameter> (--option) = <value>: allowed <range>").
void validate(const SensorOptions& o);

/// True when every model is off: the generator's output is then the paper's ideal cloud.
bool isIdeal(const SensorOptions& o);

/// Names of the presets: "ideal" and the drone lidar classes of docs/sensor.md.
std::span<const std::string_view> sensorPresetNames();
/// How many there are (a constant, for tables built before main).
inline constexpr std::size_t sensorPresetCount() { return 3; }
/// A preset's options; throws core::Error("sensor: --sensor '<name>' is not one of ...").
SensorOptions sensorPreset(std::string_view name);

/// The sub-rays of one beam, in the sensor frame: angular offsets (radians, across x and
/// down y of the image) from the pixel's axis and the share of the pulse's energy each
/// carries (a Gaussian beam profile, 1/e^2 at the divergence's half angle). Sub-ray 0 is the
/// axis itself. One sub-ray of weight 1 when the divergence is 0.
struct SubRay {
    double dx_rad = 0.0, dy_rad = 0.0, weight = 1.0;
};
std::vector<SubRay> footprintPattern(const SensorOptions& o);

/// Sensor-frame unit vector of sub-ray `s` of the beam whose axis is `axis` (unit): the axis
/// turned by s.dx_rad about the image's y axis and s.dy_rad about its x axis (both measured
/// perpendicular to the axis). Sub-ray {0, 0} gives `axis` bit for bit.
glm::dvec3 subRayDirection(const glm::dvec3& axis, const SubRay& s);

/// The same split for speed: a beam's frame once per pixel, then each sub-ray from the
/// tangents of its offsets.
struct BeamFrame {
    glm::dvec3 axis, across, down;
};
BeamFrame beamFrame(const glm::dvec3& axis);
glm::dvec3 subRayDirection(const BeamFrame& frame, double tan_dx, double tan_dy);

/// Per-view state handed to Sensor::trace: the pose the drone believes it flew
/// (nominal; points are placed with it) and the one it really flew (rays leave from it).
struct SensorView {
    int view = 0;
    core::Pose nominal;  // T_local_sensor as logged
    core::Pose actual;   // T_local_sensor as flown (nominal plus the GNSS/INS error)
};

/// A slot of Sensor::trace without a return.
inline constexpr float kNoReturn = -1.0f;

class Sensor {
  public:
    /// `seed` seeds every random model; reflectances come from the scene's meshes; `orbit`
    /// gives the pixel grid (a beam's neighbours). Throws core::Error for invalid options.
    Sensor(const SensorOptions& o, const OrbitOptions& orbit, const core::Scene& scene, std::uint64_t seed);
    ~Sensor();
    Sensor(const Sensor&) = delete;
    Sensor& operator=(const Sensor&) = delete;

    const SensorOptions& options() const;
    bool ideal() const;
    /// Slots per pixel that trace() fills: max_returns with ReturnMode::All and a beam
    /// footprint, else 1.
    std::size_t slotsPerPixel() const;
    /// Rays traced per pixel (the footprint's sub-rays).
    std::size_t raysPerPixel() const;
    /// Bytes of the per-thread buffers trace() keeps (for the memory plan).
    std::size_t scratchBytes() const;
    /// Bytes the sensor itself holds for the whole run (its per-pixel tables).
    std::size_t tableBytes() const;
    /// The CloudFields a cloud of this sensor carries (the ideal four plus those it fills).
    core::CloudFields fields() const;

    /// The view's nominal pose and the pose actually flown: nominal perturbed by the
    /// per-view and per-flight GNSS/INS error, drawn from (seed, view) alone.
    SensorView view(int index, const core::Pose& nominal) const;

    /// Traces `dirs.size()` consecutive pixels of one image row of a view, the first being
    /// pixel `first_pixel` (row-major) and dirs their sensor-frame unit directions
    /// (pixelDirection), into
    /// slotsPerPixel() slots each (slots.size() == dirs.size() * slotsPerPixel()); a slot
    /// without a return gets range_m = kNoReturn. Ray calls go through `caster`
    /// (intersect16 with `packets`, else intersect). Deterministic per (seed, view, pixel):
    /// thread-safe, and the result does not depend on how pixels are split between calls
    /// as long as packets start at the same pixels.
    void trace(const RayCaster& caster, const SensorView& view, std::uint64_t first_pixel,
               std::span<const glm::dvec3> dirs, std::span<core::CloudPoint> slots, bool packets) const;

    struct State;

  private:
    std::unique_ptr<State> state_;
};

}  // namespace sim
