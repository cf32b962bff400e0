// study/src/scene_metric.cpp: the visibility metric of each scene of a plan (study/scene_metric.hpp).
#include <study/scene_metric.hpp>

#include <io/scene_file.hpp>
#include <metric/clouds.hpp>
#include <metric/visibility.hpp>
#include <sim/generator.hpp>

#include <cstdio>

namespace study {

std::map<std::filesystem::path, double> sceneMetrics(const Plan& plan, double orbit_radius_m, double orbit_height_m) {
    std::map<std::filesystem::path, double> metrics;
    for (const PlanTrial& t : plan.trials) {
        if (t.scene.empty() || metrics.count(t.scene)) continue;
        std::fprintf(stderr, "ladarvr: study: visibility metric of %s\n", t.scene.string().c_str());
        const core::Scene scene = io::loadScene(t.scene);
        sim::GenerateOptions g;
        g.orbit.xres = plan.xres;
        g.orbit.yres = plan.yres;
        g.orbit.views = plan.views;
        const metric::MetricClouds clouds = metric::generateClouds(scene, g);
        metric::MetricOptions m;
        m.orbit.radius_m = orbit_radius_m;
        m.orbit.altitude_m = orbit_height_m;
        metric::Evaluator evaluator(clouds, &scene);
        metrics[t.scene] = evaluator.run(m).metric_mean;
    }
    return metrics;
}

}  // namespace study
