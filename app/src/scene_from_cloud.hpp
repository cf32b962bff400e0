// app/src/scene_from_cloud.hpp: `ladarvr scene from-cloud`, added under `scene` by
// cmd_scene.cpp.
#pragma once
#include <CLI/CLI.hpp>

namespace app {

/// Adds `from-cloud` and its options to the `scene` command.
void addSceneFromCloud(CLI::App& scene);

}  // namespace app
