// sim/src/sensor_models.hpp: the sensor models behind sim::Sensor, one file each
// (sensor_noise.cpp, sensor_pose.cpp, sensor_intensity.hpp, sensor_footprint.cpp,
// sensor_returns.cpp). Equations and parameters: docs/sensor.md.
#pragma once
#include "sensor_intensity.hpp"

#include <sim/sensor.hpp>

#include <cstddef>
#include <cstdint>

namespace sim::sensor_model {

// ---- sensor_noise.cpp: counter-based random numbers and the range error -------------

/// Streams of random numbers, so that no two models draw the same numbers.
enum class Stream : std::uint64_t { Range = 1, PoseView = 2, PoseFlight = 3 };

/// A 64-bit key from (seed, stream, a, b) by SplitMix64 finalisers: the same inputs give
/// the same key on every thread and run.
std::uint64_t key(std::uint64_t seed, Stream stream, std::uint64_t a, std::uint64_t b);
/// A standard normal number, the n-th (n = 0, 1, 2, ...) drawn from `k` (Box-Muller).
double gaussian(std::uint64_t k, std::uint64_t n);

/// The range error (metres) of return `ret` of pixel `pixel` of view `view`:
/// N(0, o.range_noise_m^2); 0 when the model is off.
double rangeError_m(const SensorOptions& o, std::uint64_t seed, int view, std::uint64_t pixel, int ret);

// ---- sensor_pose.cpp: GNSS/INS error ------------------------------------------------

/// T_local_sensor actually flown at `view`: the nominal pose moved by the per-flight bias
/// plus the per-view error (position per axis, attitude as roll/pitch/yaw about the
/// sensor's axes). The nominal pose itself when both are 0.
core::Pose actualPose(const SensorOptions& o, std::uint64_t seed, int view, const core::Pose& nominal);

// ---- sensor_returns.cpp: echoes of one pulse into returns --------------------------

/// One sub-ray's echo: its range and the power it brings back (weighted by its share).
struct Echo {
    float t = 0.0f;
    double power = 0.0;
    std::uint32_t sub = 0;  // sub-ray index within the beam
};

/// A return: the echoes of one surface (consecutive ranges less than a range resolution
/// apart), their summed power, and the strongest of them, which places the return.
struct Return {
    std::uint32_t strongest = 0;  // index into the echoes (after sorting)
    double power = 0.0;
};

/// Sorts `echoes` by range (then sub-ray) and groups them into returns as a waveform of
/// pulses `resolution_m` wide would separate them; drops returns whose power is below
/// min_power; keeps those `mode` asks for (ReturnMode::All: the first max_returns).
/// Writes them, in range order, to `out` (capacity max_returns, at least 1) and returns
/// how many; *detected receives the number of returns the pulse gave (before selection).
std::size_t formReturns(std::span<Echo> echoes, double resolution_m, double min_power, ReturnMode mode, int max_returns,
                        std::span<Return> out, int* detected, int* first_rank);

}  // namespace sim::sensor_model
