// app/src/sensor_options.hpp: the Ladar sensor's options of `ladarvr generate` (docs/sensor.md).
#pragma once
#include <sim/sensor.hpp>

#include <CLI/CLI.hpp>

namespace app {

/// Adds --sensor PRESET and one option per sensor model to `cmd`. Once `cmd` is parsed,
/// `out` holds the preset with every option given explicitly applied over it, validated
/// (sim::validate: core::Error naming the option and the allowed range). `out` must
/// outlive `cmd`.
void addSensorOptions(CLI::App& cmd, sim::SensorOptions& out);

}  // namespace app
