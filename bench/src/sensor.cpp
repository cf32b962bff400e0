// bench/src/sensor.cpp: what each sensor model costs against the ideal sensor, on the
// paper's configuration (demo scene, 128x128 x 100 views). Every row is the same run with
// one model on; the rows are interleaved within each repeat so that the machine's load
// drifts over all of them alike. The cast stage (rays made, traced and turned into
// returns) is where the models' cost lies; --white leaves RANSAC, which is not the
// sensor's, out of the total.
#include "sensor.hpp"

#include "common.hpp"

#include <sim/sensor.hpp>

#include <cstdio>
#include <functional>
#include <sstream>
#include <thread>
#include <vector>

namespace bench {
namespace {

struct Row {
    std::string name;
    sim::SensorOptions sensor;
    std::vector<double> cast_s, total_s;
    std::uint64_t pulses = 0, rays = 0, points = 0;
};

std::vector<Row> rows() {
    std::vector<Row> r;
    const auto add = [&](std::string name, const std::function<void(sim::SensorOptions&)>& set) {
        Row row;
        row.name = std::move(name);
        set(row.sensor);
        r.push_back(std::move(row));
    };
    add("ideal (default)", [](sim::SensorOptions&) {});
    add("--range-noise-m 0.02", [](sim::SensorOptions& o) { o.range_noise_m = 0.02; });
    add("--pose-noise-m 0.05 --attitude-noise-deg 0.057", [](sim::SensorOptions& o) {
        o.pose_noise_m = 0.05;
        o.attitude_noise_deg = 0.057;
    });
    add("--max-range-m 440", [](sim::SensorOptions& o) { o.max_range_m = 440.0; });
    add("--intensity", [](sim::SensorOptions& o) { o.intensity = true; });
    for (int q = 1; q <= 3; ++q)
        add("--beam-divergence-mrad 0.5 --footprint-quality " + std::to_string(q), [q](sim::SensorOptions& o) {
            o.beam_divergence_mrad = 0.5;
            o.footprint_quality = q;
        });
    add("--beam-divergence-mrad 0.5 --footprint-quality 3 --footprint-exact", [](sim::SensorOptions& o) {
        o.beam_divergence_mrad = 0.5;
        o.footprint_exact = true;
    });
    add("--beam-divergence-mrad 0.5 --footprint-quality 3 --returns all", [](sim::SensorOptions& o) {
        o.beam_divergence_mrad = 0.5;
        o.returns = sim::ReturnMode::All;
    });
    add("elliptical 0.5 x 1.6 mrad, q 3, --returns all", [](sim::SensorOptions& o) {
        o.beam_divergence_mrad = 0.5;
        o.beam_divergence_y_mrad = 1.6;
        o.returns = sim::ReturnMode::All;
    });
    add("--sensor riegl-vux1uav", [](sim::SensorOptions& o) { o = sim::sensorPreset("riegl-vux1uav"); });
    add("--sensor livox-avia", [](sim::SensorOptions& o) { o = sim::sensorPreset("livox-avia"); });
    return r;
}

}  // namespace

void benchSensorModels(const core::Scene& scene, const sim::GenerateOptions& paper, bool quick, bool alone,
                       const std::string& md) {
    const auto start = Clock::now();
    const int repeats = quick ? 3 : 5;
    std::vector<Row> table = rows();
    sim::GenerateOptions o = paper;
    o.white = true;
    for (int k = 0; k <= repeats; ++k) {  // k = 0: warm-up
        for (Row& row : table) {
            o.sensor = row.sensor;
            sim::GenerateStats st;
            const core::PointCloud cloud = sim::generateCloud(scene, o, &st);
            row.pulses = st.rays;
            row.rays = st.sub_rays_traced;
            row.points = st.points;
            if (k == 0) continue;
            row.cast_s.push_back(st.seconds.cast);
            row.total_s.push_back(st.seconds.total);
        }
        std::fprintf(stderr, "bench generate: sensor models, run %d/%d\n", k, repeats);
    }
    const Spread ideal = spread(table.front().cast_s);
    std::ostringstream s;
    s << "| sensor | rays per run (every sub-ray) | points | cast (s) | pulses/s (M) | cast / ideal | total (s) |\n"
      << "|---|---|---|---|---|---|---|\n";
    for (const Row& row : table) {
        const Spread cast = spread(row.cast_s);
        std::vector<double> mpulses;
        for (double t : row.cast_s) mpulses.push_back(double(row.pulses) / t / 1e6);
        s << "| " << row.name << " | " << row.rays << " | " << row.points << " | " << fmtSpread("%.3f", cast) << " | "
          << fmtSpread("%.2f", spread(mpulses)) << " | " << fmt("%.2fx", cast.median / ideal.median)
          << spreadNote(cast, ideal) << " | " << fmtSpread("%.3f", spread(row.total_s)) << " |\n";
    }
    const std::string tbl = s.str();
    std::printf("\nSensor models, paper configuration (%dx%d x %d views, --white), medians of %d runs:\n%s",
                o.orbit.xres, o.orbit.yres, o.orbit.views, repeats, tbl.c_str());
    if (md.empty()) return;
    std::ostringstream m;
    m << "## Sensor models (ladarvr bench generate)\n\n"
      << "Command: `./ladarvr bench generate" << (quick ? " --quick" : "") << (alone ? " --only sensors" : "")
      << "`; machine: " << std::thread::hardware_concurrency() << " cores, " << cpuName() << "; " << utcNow() << "; "
      << fmt("%.0f", secondsSince(start)) << " s for these rows.\n\n"
      << "Each row is the paper's configuration on the demo scene (" << o.orbit.xres << "x" << o.orbit.yres << " px x "
      << o.orbit.views
      << " views, --white so that RANSAC, which is not the sensor's, is left out) "
         "with one sensor model on (docs/sensor.md); the rows run interleaved, one after the other in each of "
      << repeats
      << " repeats after a warm-up. Cast = the generator's cast stage (rays made, traced as "
         "16-ray packets, hits turned into returns); pulses/s counts every pixel of every view, as the "
         "generator rows above do; 'rays per run' counts every sub-ray of every beam, of which the "
         "default (not --footprint-exact) traces only those of beams not on one plane, plus about one axis ray "
         "per beam for the planar test. Figures are 'median "
         "[min..max]'; cast / ideal is the ratio of medians, '(within spread)' where the two ranges overlap. "
         "Goal: a 19-ray footprint (q = 3) under 8x the ideal sensor. The machine's cores may be shared "
         "with other jobs: read the ratios rather than lone times.\n\n"
      << tbl << "\n";
    replaceMarkdownSection(md, "## Sensor models (ladarvr bench generate)", m.str());
}

}  // namespace bench
