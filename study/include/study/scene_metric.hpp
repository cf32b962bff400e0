// study/scene_metric.hpp: the paper's visibility metric (§IV-B) of each scene a plan's
// trials name, for trials.csv's visibility_metric column: computed as `ladarvr metric`
// does over its default orbit at the study's orbit radius and height, from a cloud
// generated with the plan's `generate` settings.
#pragma once
#include <study/plan.hpp>

#include <filesystem>
#include <map>

namespace study {

/// The metric's mean of every scene of `plan`, once per scene however many trials name
/// it (cloud trials have none). Renders with its own EGL context, so it runs before the
/// viewer's window opens. Prints "ladarvr: study: visibility metric of <scene>" on stderr
/// as each starts. Throws what loading, generating or the metric throws.
std::map<std::filesystem::path, double> sceneMetrics(const Plan& plan, double orbit_radius_m, double orbit_height_m);

}  // namespace study
