// bench/src/sensor.hpp: the sensor models' rows of `ladarvr bench generate`.
#pragma once
#include <core/scene.hpp>
#include <sim/generator.hpp>

#include <string>

namespace bench {

/// Times the cast stage of `paper` (the paper's configuration) on `scene` with each
/// sensor model on alone, the footprint at q = 1, 2, 3 and the presets, interleaved with
/// the ideal sensor; prints the table and, when `md` is not empty, rewrites the section
/// "## Sensor models (ladarvr bench generate)" of that file (`alone`: the command was
/// `bench generate --only sensors`).
void benchSensorModels(const core::Scene& scene, const sim::GenerateOptions& paper, bool quick, bool alone,
                       const std::string& md);

}  // namespace bench
