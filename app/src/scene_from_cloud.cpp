// app/src/scene_from_cloud.cpp: `ladarvr scene from-cloud SURVEY --out DIR [--voxel-m V]
// [--cell-m C] [--max-boxes N] [--coarsen] [--max-height-m H] [--ground-from
// auto|classes|filter] [--method smrf|csf] [--vehicle MESH|vehicles.json [--family F] [--vehicle-up y|z]
// [--vehicle-at X,Y] [--yaw-deg D] [--seed S] ...]`: a real survey turned into a scene
// folder the generator reads (sim/scene_from_cloud.hpp). Options are parsed and checked
// here; the work is sim::buildSceneFromCloud and sim::writeSceneFolder.
#include "scene_from_cloud.hpp"

#include "cli_common.hpp"
#include "ground_options.hpp"

#include <core/error.hpp>
#include <io/cloud_reader.hpp>
#include <platform/input_set.hpp>
#include <platform/progress.hpp>
#include <platform/safe_file.hpp>
#include <sim/scene_from_cloud.hpp>

#include <core/random.hpp>

#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

namespace app {
namespace {

struct SceneFromCloudCli {
    std::string survey, out, ground_from = "auto", method = "smrf", vehicle, vehicle_at, family, vehicle_up = "z";
    std::optional<double> yaw_deg;
    sim::SceneFromCloudOptions options;
};

sim::SceneGroundSource groundSource(const std::string& text) {
    if (text == "auto") return sim::SceneGroundSource::Auto;
    if (text == "classes") return sim::SceneGroundSource::Classes;
    if (text == "filter") return sim::SceneGroundSource::Filter;
    throw core::Error("scene from-cloud: --ground-from '" + core::printable(text) +
                      "' is not one of auto, classes, filter");
}

// The largest vehicles.json read: scripts/make_vehicles.py's list is kilobytes.
constexpr std::size_t kMaxVehicleListBytes = std::size_t(16) << 20;

// --vehicle naming scripts/make_vehicles.py's vehicles.json: one of its vehicles (of
// --family when given) drawn with the seed, its mesh beside the list. Returns the mesh and
// sets `family` to the one drawn.
std::filesystem::path drawVehicle(const std::filesystem::path& list, std::string& family, std::uint64_t seed) {
    const std::string where = "scene from-cloud: --vehicle " + core::printable(list.string(), 400);
    const nlohmann::json j =
        nlohmann::json::parse(platform::readTextFile(list, kMaxVehicleListBytes, where), nullptr, false);
    if (!j.is_object() || !j.contains("vehicles") || !j["vehicles"].is_array())
        throw core::Error(where +
                          ": not a vehicle list; allowed a mesh file or scripts/make_vehicles.py's "
                          "vehicles.json (an object whose \"vehicles\" is a list)");
    std::vector<std::pair<std::string, std::string>> found;  // file, family
    for (const nlohmann::json& v : j["vehicles"]) {
        if (!v.is_object() || !v.contains("file") || !v["file"].is_string() || !v.contains("family") ||
            !v["family"].is_string())
            throw core::Error(where +
                              ": a vehicle without a \"file\" and a \"family\" string; allowed "
                              "scripts/make_vehicles.py's vehicles.json");
        if (family.empty() || v["family"].get<std::string>() == family)
            found.emplace_back(v["file"].get<std::string>(), v["family"].get<std::string>());
    }
    if (found.empty())
        throw core::Error(where + ": no vehicle" +
                          (family.empty() ? "" : " of --family '" + core::printable(family) + "'") +
                          "; allowed a family the list holds");
    core::SplitMix64 rng(seed ^ 0x76656869636C65ull);  // "vehicle": a stream apart from the spot's
    const auto& [file, drawn] = found[std::size_t(rng.below(found.size()))];
    const std::filesystem::path name(file);
    if (name.empty() || name.is_absolute() || name.has_parent_path())
        throw core::Error(where + ": vehicle file '" + core::printable(file) +
                          "'; allowed a file name beside the list");
    family = drawn;
    return list.parent_path() / name;
}

void run(SceneFromCloudCli& cli) {
    const auto t0 = std::chrono::steady_clock::now();
    sim::SceneFromCloudOptions& o = cli.options;
    o.ground_source = groundSource(cli.ground_from);
    o.ground.method = sim::parseGroundMethod(cli.method, "scene from-cloud: --method");
    if (!cli.family.empty() && !cli.vehicle.ends_with(".json"))
        throw core::Error("scene from-cloud: --family needs --vehicle naming a vehicles.json list");
    std::filesystem::path list;  // a vehicles.json the mesh was drawn from
    if (cli.vehicle.ends_with(".json")) {
        list = cli.vehicle;
        platform::checkInputFile(cli.vehicle, "scene from-cloud: --vehicle " + core::printable(cli.vehicle, 400));
        cli.vehicle = drawVehicle(cli.vehicle, cli.family, o.vehicle.seed).string();
        std::fprintf(stderr, "scene from-cloud: vehicle %s (%s) drawn from the list\n",
                     platform::messageLine(cli.vehicle, 400).c_str(), cli.family.c_str());
    }
    o.vehicle.mesh = cli.vehicle;
    o.vehicle.yaw_deg = cli.yaw_deg;
    if (cli.vehicle_up != "z" && cli.vehicle.empty())
        throw core::Error("scene from-cloud: --vehicle-up needs --vehicle");
    o.vehicle.up_y = cli.vehicle_up == "y";
    if (!cli.vehicle_at.empty()) {
        if (cli.vehicle.empty()) throw core::Error("scene from-cloud: --vehicle-at needs --vehicle");
        const glm::dvec3 at = parseWorldTriple(cli.vehicle_at + ",0", "scene from-cloud: --vehicle-at");
        o.vehicle.at_world = glm::dvec2(at);
    }
    sim::validate(o);
    const std::filesystem::path survey = cli.survey, out = cli.out;
    platform::checkDistinctPaths("scene from-cloud",
                                 {{"survey", survey, platform::PathRole::Input, {}},
                                  {"--vehicle", cli.vehicle, platform::PathRole::Input, {}},
                                  {"--out", out, platform::PathRole::OutputFolder, sim::isSceneFromCloudFile}});
    platform::checkInputFile(survey, "scene from-cloud: survey " + core::printable(cli.survey, 400));
    if (!cli.vehicle.empty())
        platform::checkInputFile(cli.vehicle, "scene from-cloud: --vehicle " + core::printable(cli.vehicle, 400));
    platform::InputSet inputs;
    inputs.addFile(survey);
    if (!cli.vehicle.empty()) inputs.addFile(cli.vehicle);
    if (!list.empty()) inputs.addFile(list);
    for (const char* name : {"scene.json", "ground.obj", "environment.obj", "from_cloud.json"})
        inputs.checkNotAnInput(out / name);

    std::size_t declared = 0;
    {
        const io::CloudReader reader(survey);  // the header checked before the work
        declared = reader.declaredPoints();
    }
    platform::Progress progress("scene from-cloud: reading", 3 * declared);
    const sim::SceneFromCloud s = sim::buildSceneFromCloud(survey, o, [&](std::size_t n) { progress.advance(n); });
    progress.finish();
    if (!s.reader_warning.empty()) platform::printMessage("warning", s.reader_warning);
    if (!s.units.metres())
        std::fprintf(stderr, "scene from-cloud: coordinates in %s: converted to metres\n",
                     sim::describe(s.units).c_str());
    if (s.voxel_m != s.voxel_requested_m)
        std::fprintf(stderr,
                     "scene from-cloud: more than --max-boxes %zu boxes at --voxel-m %g: coarsened to %g m voxels "
                     "(%zu boxes)\n",
                     o.max_boxes, s.voxel_requested_m, s.voxel_m, s.boxes.size());
    if (s.dropped_high + s.dropped_low > 0)
        std::fprintf(stderr,
                     "scene from-cloud: outliers that made no box: %zu more than --max-height-m %g m above the "
                     "terrain, %zu more than %g m below it\n",
                     s.dropped_high, o.max_height_m, s.dropped_low, sim::kSurveyLowOutlier_m);
    if (s.vehicle) inputs.checkNotAnInput(out / s.vehicle->file);
    sim::writeSceneFolder(out, s, o);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf(
        "scene from-cloud: wrote %s: %zu points, %zu ground (%s), terrain %d x %d nodes every %g m, %zu "
        "boxes of %g m, offset %.3f %.3f %.3f",
        platform::messageLine(cli.out, 400).c_str(), s.points, s.ground_points, s.ground_from.c_str(), s.terrain.nx,
        s.terrain.ny, s.terrain.cell_m, s.boxes.size(), s.voxel_m, s.offset_m.x, s.offset_m.y, s.offset_m.z);
    if (s.vehicle)
        std::printf(", vehicle at %.2f %.2f %.2f (yaw %g deg, slope %.3f)", s.vehicle->footprint_centre.x,
                    s.vehicle->footprint_centre.y, s.vehicle->footprint_centre.z, s.vehicle->yaw_deg, s.vehicle->slope);
    std::printf(", %.3f s\n", seconds);
}

}  // namespace

void addSceneFromCloud(CLI::App& scene) {
    auto state = std::make_shared<SceneFromCloudCli>();
    sim::SceneFromCloudOptions& o = state->options;
    CLI::App* c = scene.add_subcommand(
        "from-cloud",
        "turn a real survey (LAS/LAZ/COPC, PCD, PLY) into a scene folder: its ground as a terrain mesh, its other "
        "points as voxel boxes, a vehicle on its ground as the target, for generate");
    c->add_option("survey", state->survey, "the survey cloud; it is never overwritten")->required();
    c->add_option("--out", state->out, "the scene folder to write (replaced as a whole)")->required();
    c->add_option("--voxel-m", o.voxel_m, "edge of the boxes made of the points that are not ground, (0.05, 100] m")
        ->capture_default_str();
    c->add_option("--cell-m", o.cell_m,
                  "terrain grid spacing, [0.1, 100] m; 0: 1.5 times the ground points' spacing, within [1, 10] m")
        ->capture_default_str();
    c->add_option("--max-boxes", o.max_boxes, "boxes at most, 1..50000000; past it refused unless --coarsen")
        ->capture_default_str();
    c->add_option("--max-height-m", o.max_height_m,
                  "points more than this above the terrain (birds, noise) make no box, (0, 10000] m; those more than "
                  "6 m below it neither")
        ->capture_default_str();
    c->add_flag("--coarsen", o.coarsen, "past --max-boxes, double the voxel until the boxes fit instead of refusing");
    c->add_option("--ground-from", state->ground_from,
                  "auto (class 2 where at least 1 % of the points are class 2, else the filter), classes or filter")
        ->capture_default_str();
    c->add_option("--method", state->method, "the ground filter where it runs: smrf or csf (ladarvr ground's)")
        ->capture_default_str();
    addSmrfOptions(*c, o.ground.smrf);
    addCsfOptions(*c, o.ground.csf);
    c->add_option("--vehicle", state->vehicle,
                  "a vehicle mesh (e.g. one of scripts/make_vehicles.py's OBJ files), or that script's "
                  "vehicles.json to draw one with --seed; copied into the folder (as target.obj, z up, when a .gltf "
                  "or --vehicle-up y) and put on the ground as the target");
    c->add_option("--vehicle-up", state->vehicle_up, "the vehicle mesh's up axis: z, or y (glTF's)")
        ->check(CLI::IsMember({"y", "z"}))
        ->capture_default_str();
    c->add_option("--family", state->family,
                  "with --vehicle naming a vehicles.json list: draw a vehicle of this family only (car, tank, ...)");
    c->add_option("--vehicle-at", state->vehicle_at,
                  "x,y of the vehicle's centre in the survey's coordinates (metres); default: a random flat, free "
                  "spot");
    c->add_option("--yaw-deg", state->yaw_deg, "the vehicle's heading, [-360, 360] degrees; default: random");
    c->add_option("--seed", o.vehicle.seed, "seed of the random spot and heading")->capture_default_str();
    c->add_option("--max-slope", o.vehicle.max_slope, "flat enough: the ground's slope under the vehicle, [0, 1]")
        ->capture_default_str();
    c->add_option("--max-roughness-m", o.vehicle.max_roughness_m,
                  "the ground under the vehicle at most this far off its plane, [0, 10] m")
        ->capture_default_str();
    c->add_option("--clearance-m", o.vehicle.clearance_m,
                  "free: no box within this distance of the vehicle's footprint, [0, 100] m")
        ->capture_default_str();
    c->callback([state] { run(*state); });
}

}  // namespace app
