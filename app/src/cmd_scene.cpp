// app/src/cmd_scene.cpp: `ladarvr scene info [SCENE]`: what a scene holds, measured
// (core::summarize): each mesh's role, file, triangles, size and position, the target's
// size and height above the ground under it, and the warnings `generate` would print.
// `ladarvr scene from-cloud` (a scene made from a real survey) is scene_from_cloud.cpp.
#include "cli_common.hpp"
#include "commands.hpp"
#include "scene_from_cloud.hpp"

#include <core/scene_info.hpp>
#include <io/scene_file.hpp>

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

namespace app {
namespace {

struct SceneInfoCli {
    std::string scene;
    bool json = false;
};

nlohmann::json vec(const glm::dvec3& v) { return {v.x, v.y, v.z}; }

nlohmann::json optionalNumber(const std::optional<double>& v) {
    return v ? nlohmann::json(*v) : nlohmann::json(nullptr);
}

nlohmann::json toJson(const core::SceneSummary& s, const std::filesystem::path& path) {
    nlohmann::json j;
    j["scene"] = std::filesystem::absolute(path).string();
    j["origin"] = vec(s.origin);
    j["triangles"] = s.triangles;
    j["bounds_world"] = {{"lo", vec(s.origin + s.bounds.lo)}, {"hi", vec(s.origin + s.bounds.hi)}};
    j["meshes"] = nlohmann::json::array();
    for (const core::MeshSummary& m : s.meshes)
        j["meshes"].push_back(
            {{"file", m.file},
             {"role", std::string(core::roleName(m.role))},
             {"triangles", m.triangles},
             {"size_m", vec(m.bounds.size())},
             {"position", vec(m.position)},
             {"bounds_world", {{"lo", vec(s.origin + m.bounds.lo)}, {"hi", vec(s.origin + m.bounds.hi)}}}});
    if (s.target) {
        const core::TargetSummary& t = *s.target;
        j["target"] = {
            {"size_m", vec(t.bounds.size())},
            {"centre_world", vec(s.origin + t.bounds.centre())},
            {"bottom_z_world", s.origin.z + t.bounds.lo.z},
            {"ground_z_world", t.ground_z ? nlohmann::json(s.origin.z + *t.ground_z) : nlohmann::json(nullptr)},
            {"height_above_ground_m", optionalNumber(t.height_above_ground_m)}};
    } else {
        j["target"] = nullptr;
    }
    j["warnings"] = core::targetWarnings(s);
    return j;
}

// x, y, z with `decimals` decimals joined by `separator`; values that round to zero print
// as 0, never -0.
std::string triple(const glm::dvec3& v, int decimals, const char* separator = " ") {
    const double half_step = 0.5 * std::pow(10.0, -decimals);
    std::string out;
    for (int k = 0; k < 3; ++k) {
        char buffer[64];
        std::snprintf(buffer, sizeof buffer, "%.*f", decimals, std::abs(v[k]) < half_step ? 0.0 : v[k]);
        out += (k ? separator : "") + std::string(buffer);
    }
    return out;
}

void printHuman(const core::SceneSummary& s, const std::filesystem::path& path) {
    std::printf("scene %s: %zu meshes, %zu triangles, origin %s\n", path.string().c_str(), s.meshes.size(), s.triangles,
                triple(s.origin, 3).c_str());
    std::printf("  %-4s %-11s %9s  %-26s  %-30s  %s\n", "#", "role", "triangles", "size x y z (m)",
                "position x y z (m)", "file");
    for (std::size_t i = 0; i < s.meshes.size(); ++i) {
        const core::MeshSummary& m = s.meshes[i];
        std::printf("  %-4zu %-11s %9zu  %-26s  %-30s  %s\n", i, std::string(core::roleName(m.role)).c_str(),
                    m.triangles, triple(m.bounds.size(), 2, " x ").c_str(), triple(m.position, 3).c_str(),
                    m.file.c_str());
    }
    if (!s.target) {
        std::printf("target: none (generate needs one)\n");
        return;
    }
    const core::TargetSummary& t = *s.target;
    std::printf("target: size %s m, centre %s, bottom at z = %.3f\n", triple(t.bounds.size(), 2, " x ").c_str(),
                triple(s.origin + t.bounds.centre(), 3).c_str(), s.origin.z + t.bounds.lo.z);
    if (t.height_above_ground_m)
        std::printf("target: height above the ground under its centre %.3f m (ground at z = %.3f)\n",
                    *t.height_above_ground_m, s.origin.z + *t.ground_z);
    else
        std::printf("target: no ground under its centre\n");
    for (const std::string& w : core::targetWarnings(s)) std::printf("warning: %s\n", w.c_str());
}

void run(const SceneInfoCli& cli) {
    const std::filesystem::path path = cli.scene.empty() ? io::demoScenePath() : std::filesystem::path(cli.scene);
    io::SceneLoadOptions options;
    options.require_target = false;  // describe any scene; say so when it has no target
    const core::Scene scene = io::loadScene(path, options);
    const core::SceneSummary summary = core::summarize(scene);
    if (cli.json)
        std::printf("%s\n", toJson(summary, path).dump(2).c_str());
    else
        printHuman(summary, path);
}

}  // namespace

void registerScene(CLI::App& cli) {
    CLI::App* scene = cli.add_subcommand("scene", "inspect a scene file, or make one from a real survey");
    scene->require_subcommand(1);
    auto state = std::make_shared<SceneInfoCli>();
    CLI::App* info = scene->add_subcommand(
        "info",
        "each mesh's role, file, triangles, size and position; the target's size and height above "
        "the ground under it; what generate would warn about");
    info->add_option("scene", state->scene, "scene file (JSON); default: the bundled demo scene");
    info->add_flag("--json", state->json, "print the same as JSON on stdout");
    info->callback([state] { run(*state); });
    addSceneFromCloud(*scene);
}

}  // namespace app
