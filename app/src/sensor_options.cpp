// app/src/sensor_options.cpp: --sensor and the sensor models' options of `ladarvr
// generate`. A preset sets every model; an option given on the command line overrides
// the preset's value for that model alone, whatever the order of the two.
#include "sensor_options.hpp"

#include <core/error.hpp>

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace app {
namespace {

struct SensorCli {
    std::string preset = "ideal";
    std::string returns;
    sim::SensorOptions given;                                     // the values as parsed
    std::vector<std::function<void(sim::SensorOptions&)>> apply;  // copies one given value, if given
};

std::string presetList() {
    std::string names;
    for (std::string_view n : sim::sensorPresetNames()) names += (names.empty() ? "" : ", ") + std::string(n);
    return names;
}

}  // namespace

void addSensorOptions(CLI::App& cmd, sim::SensorOptions& out) {
    auto cli = std::make_shared<SensorCli>();
    sim::SensorOptions& g = cli->given;
    // Registers option `name` bound to member `field` of the given options.
    const auto add = [&](const char* name, auto sim::SensorOptions::* field, const std::string& help) {
        CLI::Option* opt = cmd.add_option(name, g.*field, help);
        cli->apply.push_back([opt, field, c = cli.get()](sim::SensorOptions& o) {
            if (opt->count() > 0) o.*field = c->given.*field;
        });
    };
    cmd.add_option("--sensor", cli->preset,
                   "sensor preset: " + presetList() + " (docs/sensor.md); the options below override it")
        ->capture_default_str();
    add("--range-noise-m", &sim::SensorOptions::range_noise_m, "sigma of the Gaussian range error, [0, 100] m");
    add("--pose-noise-m", &sim::SensorOptions::pose_noise_m,
        "GNSS/INS position error per view, sigma per axis, [0, 100] m");
    add("--attitude-noise-deg", &sim::SensorOptions::attitude_noise_deg,
        "GNSS/INS attitude error per view, sigma per axis, [0, 10] deg");
    add("--pose-bias-m", &sim::SensorOptions::pose_bias_m,
        "GNSS/INS position error drawn once per flight, sigma per axis, [0, 100] m");
    add("--attitude-bias-deg", &sim::SensorOptions::attitude_bias_deg,
        "GNSS/INS attitude error drawn once per flight, sigma per axis, [0, 10] deg");
    add("--max-range-m", &sim::SensorOptions::max_range_m, "echoes beyond are lost, [0, 1e7] m, 0 = no limit");
    CLI::Option* intensity = cmd.add_flag("--intensity", g.intensity,
                                          "fill intensity (lidar equation, per-mesh 'reflectance') and incidence");
    cli->apply.push_back([intensity, c = cli.get()](sim::SensorOptions& o) {
        if (intensity->count() > 0) o.intensity = c->given.intensity;
    });
    add("--intensity-reference-range-m", &sim::SensorOptions::intensity_reference_range_m,
        "range at which reflectance 1 at normal incidence reads 65535, [0.001, 1e7] m");
    add("--min-intensity", &sim::SensorOptions::min_intensity,
        "echoes weaker than this are lost, [0, 65535] (LAS intensity counts)");
    add("--beam-divergence-mrad", &sim::SensorOptions::beam_divergence_mrad,
        "full beam divergence at 1/e^2 across the image, [0, 100] mrad, 0 = a thin beam");
    add("--beam-divergence-y-mrad", &sim::SensorOptions::beam_divergence_y_mrad,
        "the same down the image for an elliptical footprint, [0, 100] mrad, 0 = circular");
    add("--footprint-quality", &sim::SensorOptions::footprint_quality,
        "q: footprint sampled by 1 + sum_{k<q} int(2 pi k) sub-rays (q = 3: 19), [1, 5]");
    CLI::Option* exact = cmd.add_flag("--footprint-exact", g.footprint_exact,
                                      "trace every sub-ray of every beam, also of beams whose neighbourhood "
                                      "lies on one plane");
    cli->apply.push_back([exact, c = cli.get()](sim::SensorOptions& o) {
        if (exact->count() > 0) o.footprint_exact = c->given.footprint_exact;
    });
    cmd.add_option("--returns", cli->returns, "returns kept per pulse: first (default), last, strongest, all");
    add("--max-returns", &sim::SensorOptions::max_returns, "returns per pulse at most with --returns all, [1, 15]");
    add("--pulse-ns", &sim::SensorOptions::pulse_ns, "pulse width, [0.01, 1000] ns (range resolution c*pulse/2)");
    add("--range-resolution-m", &sim::SensorOptions::range_resolution_m,
        "echoes closer than this merge into one return, [0, 1000] m, 0 = c*pulse/2");
    cmd.parse_complete_callback([cli, &out] {
        sim::SensorOptions o = sim::sensorPreset(cli->preset);
        for (const auto& apply : cli->apply) apply(o);
        if (!cli->returns.empty()) o.returns = sim::parseReturnMode(cli->returns, "sensor: --returns");
        sim::validate(o);
        out = o;
    });
}

}  // namespace app
