// app/src/cmd_generate.cpp: `ladarvr generate`: the drone Ladar simulation of paper §III.
// Parses and validates every option before any work (the error names the option and the
// allowed range), loads the scene, runs sim::Generator streaming into the output file,
// prints a human summary on stderr and, with --json, a JSON summary on stdout.
#include "cli_common.hpp"
#include "commands.hpp"
#include "ground_options.hpp"
#include "sensor_options.hpp"

#include <core/error.hpp>
#include <core/scene_info.hpp>
#include <io/cloud_io.hpp>
#include <io/scene_file.hpp>
#include <platform/atomic_file.hpp>
#include <platform/input_set.hpp>
#include <platform/safe_file.hpp>
#include <sim/generator.hpp>
#include <sim/memory_budget.hpp>

#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

namespace app {
namespace {

namespace fs = std::filesystem;

struct GenerateCli {
    std::string scene;
    std::string out;
    std::string format;
    std::string roles;
    std::string centre;
    bool json = false;
    bool skip_nonfinite = false;
    bool no_skip_rays = false;
    double memory_mb = sim::kDefaultMemoryMb;
    int las_target_class = 64;
    sim::GenerateOptions options;
    GroundCli ground;
};

// Default output: out/<name>.<pcd|ply>, <name> = the scene file's stem, or its folder's
// name for the usual "<folder>/scene.json".
fs::path defaultOutput(const fs::path& scene, io::CloudFormat format) {
    std::string name = scene.stem().string();
    if (name == "scene" && !scene.parent_path().filename().empty()) name = scene.parent_path().filename().string();
    const bool ply = format == io::CloudFormat::PlyBinary || format == io::CloudFormat::PlyAscii;
    const char* ext = ply                               ? ".ply"
                      : format == io::CloudFormat::Las  ? ".las"
                      : format == io::CloudFormat::Laz  ? ".laz"
                      : format == io::CloudFormat::Copc ? ".copc.laz"
                                                        : ".pcd";
    return fs::path("out") / (name + ext);
}

const char* formatName(io::CloudFormat f) { return io::cloudFormatName(f); }

// --format and the --out extension must agree: a cloud never lands under the name of
// another format (pcd-ascii and ply-ascii go with .pcd and .ply). Other extensions are
// the user's choice once --format names the format. A COPC file is a LAZ file, so
// --format copc may go with a .laz name; a .copc.laz name is COPC only.
void checkExtension(const fs::path& out, io::CloudFormat format) {
    io::CloudFormat by_name;
    try {
        by_name = io::formatForPath(out, "generate: --out");
    } catch (const core::Error&) {
        return;
    }
    const auto family = [](io::CloudFormat f) {
        if (f == io::CloudFormat::PcdAscii) return io::CloudFormat::PcdBinary;
        if (f == io::CloudFormat::PlyAscii) return io::CloudFormat::PlyBinary;
        return f;
    };
    if (by_name == io::CloudFormat::Laz && format == io::CloudFormat::Copc) return;
    if (family(by_name) != family(format))
        throw core::Error("generate: --out " + out.string() + ": the extension does not match --format " +
                          formatName(format));
}

nlohmann::json optionalNumber(const std::optional<double>& v) {
    return v ? nlohmann::json(*v) : nlohmann::json(nullptr);
}

std::string percent(const std::optional<double>& v) {
    if (!v) return "n/a";
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.2f %%", 100.0 * *v);
    return buffer;
}

std::string roleList(core::RoleMask roles) {
    std::string s;
    for (int r = 0; r < core::kRoleCount; ++r)
        if (roles.has(core::Role(r))) s += (s.empty() ? "" : ",") + std::string(core::roleName(core::Role(r)));
    return s;
}

void run(GenerateCli& cli) {
    sim::GenerateOptions& o = cli.options;
    // Everything is checked before the scene is read or a ray is cast.
    if (!cli.roles.empty()) o.roles = core::RoleMask::parse(cli.roles, "generate: --roles");
    if (!cli.centre.empty()) o.centre = parseWorldTriple(cli.centre, "generate: --centre");
    o.memory_budget_bytes = sim::memoryBudgetBytes(cli.memory_mb, "generate");
    o.skip_rays = !cli.no_skip_rays;
    applyGroundOptions(cli.ground, o);
    sim::validate(o);
    const fs::path scene_path = cli.scene.empty() ? io::demoScenePath() : fs::path(cli.scene);
    std::optional<io::CloudFormat> format;
    if (!cli.format.empty()) format = io::parseCloudFormat(cli.format, "generate: --format");
    const fs::path out =
        cli.out.empty() ? defaultOutput(scene_path, format.value_or(io::CloudFormat::PcdBinary)) : fs::path(cli.out);
    if (format)
        checkExtension(out, *format);
    else
        format = io::formatForPath(out, "generate: --out");
    if (!(cli.las_target_class >= 0 && cli.las_target_class <= 255))
        throw core::Error("generate: --las-target-class = " + std::to_string(cli.las_target_class) +
                          ": allowed 0..255");
    o.las.class_of_role[int(core::Role::Target)] = std::uint8_t(cli.las_target_class);
    platform::checkDistinctPaths("generate", {{"--scene", scene_path, platform::PathRole::Input, {}},
                                              {"--out", out, platform::PathRole::Output, {}},
                                              {"--dtm", cli.ground.dtm, platform::PathRole::Output, {}}});
    createParentFolders(out, "generate: --out");
    platform::checkWritableDestination(out);
    prepareDtmOutput(cli.ground);
    o.progress = true;  // drawn only when stderr is a terminal

    const auto t0 = std::chrono::steady_clock::now();
    io::SceneLoadOptions load_options;
    load_options.skip_nonfinite = cli.skip_nonfinite;
    const core::Scene scene = io::loadScene(scene_path, load_options);
    if (scene.skipped_triangles > 0 || scene.skipped_nonfinite_triangles > 0)
        warn("generate: " + scene_path.string() + ": skipped " + std::to_string(scene.skipped_triangles) +
             " zero-area and " + std::to_string(scene.skipped_nonfinite_triangles) +
             " non-finite (NaN/inf vertex) triangles");
    for (const std::string& w : core::targetWarnings(core::summarize(scene)))
        warn("generate: " + scene_path.string() + ": " + w + " (see 'ladarvr scene info')");
    const double load_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    // The scene's own files are the run's inputs: no output may replace one of them.
    platform::InputSet inputs;
    for (const fs::path& file : io::sceneFiles(scene, load_options.roles)) inputs.addFile(file);
    inputs.checkNotAnInput(out);
    if (!cli.ground.dtm.empty()) inputs.checkNotAnInput(cli.ground.dtm);
    sim::GenerateStats st;
    std::unique_ptr<platform::TempFile> dtm;  // written before the cloud lands, committed after it
    {
        sim::Generator generator(scene, o);
        generator.run(out, *format, &st,
                      [&](const sim::GenerateStats& done) { dtm = stageDtm(cli.ground, done, scene.origin); });
    }
    if (dtm) dtm->commit();
    const double seconds = load_s + st.seconds.total;
    // Misses are expected when only some roles are cast; with all of them, most rays
    // missing means the orbit looks past the scene.
    if (o.roles.bits == core::RoleMask::all().bits && st.rays > 0 && 2 * st.misses > st.rays)
        warn("generate: " + std::to_string(st.misses) + " of " + std::to_string(st.rays) +
             " rays missed the scene (more than half): is the orbit (--centre, --altitude-m) or the scene "
             "misplaced? (see 'ladarvr scene info')");

    const sim::OrbitOptions& orbit = o.orbit;
    std::fprintf(stderr,
                 "generate: %s -> %s (%s)\n"
                 "  scene: %zu meshes, %zu triangles in the BVH (roles: %s), origin %.3f %.3f %.3f\n"
                 "  orbit: altitude %.2f m, CO %.2f m, alpha %.2f deg, FoV %.3f deg, %dx%d px, %d views, "
                 "centre C %.3f %.3f %.3f\n"
                 "  derived: drone radius %.2f m, length sensed %.2f m, covered diameter %.2f m\n"
                 "  rays %llu (%llu traced, the others cannot meet the geometry's bounds), hits %llu, misses %llu\n"
                 "  ground: %s, %llu labelled ground; "
                 "precision %s, recall %s; kept coloured 0.5 m above the true terrain: target %s, environment %s\n"
                 "  time: load %.3f s, BVH %.3f s, cast %.3f s, fuse %.3f s, ground %.3f s, colour %.3f s, "
                 "write %.3f s, total %.3f s (%d threads%s%s)\n",
                 scene_path.string().c_str(), out.string().c_str(), formatName(*format), scene.meshes.size(),
                 st.triangles, roleList(o.roles).c_str(), scene.origin.x, scene.origin.y, scene.origin.z,
                 orbit.altitude_m, orbit.overlap_m, orbit.inclination_deg, orbit.fov_deg, orbit.xres, orbit.yres,
                 orbit.views, st.centre.x, st.centre.y, st.centre.z, st.drone_radius_m, st.length_sensed_m,
                 st.coverage_diameter_m, (unsigned long long)st.rays, (unsigned long long)st.rays_traced,
                 (unsigned long long)st.points, (unsigned long long)st.misses, groundFoundText(o, st).c_str(),
                 (unsigned long long)st.ground_truth, percent(st.ground_precision).c_str(),
                 percent(st.ground_recall).c_str(), percent(st.target_kept).c_str(),
                 percent(st.environment_kept).c_str(), load_s, st.seconds.bvh, st.seconds.cast, st.seconds.fuse,
                 st.seconds.ground, st.seconds.colour, st.seconds.write, seconds, st.threads,
                 st.in_output  ? ", streamed into the output and coloured there"
                 : st.streamed ? ", streamed through a spool file"
                               : "",
                 st.pipelined ? "; ground and fuse beside the next views' cast, so stages overlap" : "");
    if (o.white) std::fprintf(stderr, "  --white: no colouring, no ground whitening\n");
    reportGround(cli.ground, o, st);
    if (o.threads > st.threads)
        std::fprintf(stderr, "  --threads %d lowered to %d to fit --memory-mb\n", o.threads, st.threads);

    if (cli.json) {
        nlohmann::json j;
        j["output"] = fs::absolute(out).string();
        j["format"] = formatName(*format);
        j["scene"] = fs::absolute(scene_path).string();
        j["origin"] = {scene.origin.x, scene.origin.y, scene.origin.z};
        j["centre"] = {st.centre.x, st.centre.y, st.centre.z};
        j["drone_radius_m"] = st.drone_radius_m;
        j["length_sensed_m"] = st.length_sensed_m;
        j["coverage_diameter_m"] = st.coverage_diameter_m;
        j["altitude_m"] = orbit.altitude_m;
        j["overlap_m"] = orbit.overlap_m;
        j["alpha_deg"] = orbit.inclination_deg;
        j["fov_deg"] = orbit.fov_deg;
        j["xres"] = orbit.xres;
        j["yres"] = orbit.yres;
        j["views"] = orbit.views;
        j["seed"] = o.seed;
        j["white"] = o.white;
        j["triangles"] = st.triangles;
        j["skipped_zero_area_triangles"] = st.skipped_zero_area_triangles;
        j["skipped_nonfinite_triangles"] = st.skipped_nonfinite_triangles;
        j["rays"] = st.rays;
        j["points"] = st.points;
        j["misses"] = st.misses;
        j["rays_traced"] = st.rays_traced;
        j["skip_rays"] = o.skip_rays;
        j["ground_found"] = st.ground_found;
        j["ground_truth"] = st.ground_truth;
        j["planes_accepted"] = st.planes_accepted;
        j["planes_rejected"] = st.planes_rejected;
        j["views_without_ransac"] = st.views_without_ransac;
        j["ground_precision"] = optionalNumber(st.ground_precision);
        j["ground_recall"] = optionalNumber(st.ground_recall);
        j["target_kept_coloured"] = optionalNumber(st.target_kept);
        j["environment_kept_coloured"] = optionalNumber(st.environment_kept);
        j["target_above_terrain"] = st.target_above_terrain;
        j["environment_above_terrain"] = st.environment_above_terrain;
        j["z_min_m"] = scene.origin.z + st.z_min;
        j["z_max_m"] = scene.origin.z + st.z_max;
        j["threads"] = st.threads;
        j["streamed"] = st.streamed;
        j["in_output"] = st.in_output;
        j["pipelined"] = st.pipelined;
        j["packed_on_workers"] = st.packed_on_workers;
        j["seconds"] = seconds;
        j["stage_seconds"] = {{"load", load_s},           {"bvh", st.seconds.bvh},       {"cast", st.seconds.cast},
                              {"fuse", st.seconds.fuse},  {"ground", st.seconds.ground}, {"colour", st.seconds.colour},
                              {"write", st.seconds.write}};
        addGroundJson(j, cli.ground, st);
        std::printf("%s\n", j.dump(2).c_str());
    }
}

}  // namespace

void registerGenerate(CLI::App& cli) {
    auto state = std::make_shared<GenerateCli>();
    CLI::App* c =
        cli.add_subcommand("generate",
                           "simulate the drone Ladar of paper §III: ray-cast NoV views on a circular orbit, fuse, "
                           "whiten the ground (iterative RANSAC, or SMRF or CSF: --ground), colour by height (jet, 64 "
                           "values)");
    sim::GenerateOptions& o = state->options;
    sim::OrbitOptions& orbit = o.orbit;
    c->add_option("--scene", state->scene, "scene file (JSON); default: the bundled demo scene");
    c->add_option("--out", state->out,
                  "output cloud (.pcd, .ply, .las, .laz, .copc.laz); default out/<scene name>.pcd "
                  "(.ply/.las/.laz/.copc.laz with --format)");
    c->add_option("--format", state->format,
                  "pcd (binary, default), pcd-ascii, ply (binary), ply-ascii, las, "
                  "laz, copc; default from the --out extension");
    c->add_option("--las-target-class", state->las_target_class, "LAS/LAZ: the ASPRS class of target points, 0..255")
        ->capture_default_str();
    c->add_option("--node-points", o.copc_node_points,
                  "COPC output: the most points a node of the octree holds (larger nodes make a smaller file, "
                  "smaller ones let a viewer load the cloud in finer steps)")
        ->capture_default_str();
    c->add_option("--drone-speed-mps", o.drone_speed_mps,
                  "LAS/LAZ: drone speed along the orbit, m/s > 0 (sets each view's GPS time)")
        ->capture_default_str();
    c->add_flag("--white", o.white, "write the uncoloured (white) cloud: no colour map, no ground filter");
    c->add_flag("--no-skip-rays", state->no_skip_rays,
                "trace every pixel, also those whose rays cannot meet the ray-cast geometry's bounds "
                "(same cloud, slower; for comparisons)");
    c->add_flag("--skip-nonfinite", state->skip_nonfinite,
                "drop triangles with a NaN/inf vertex (counted in a warning) instead of failing");
    c->add_option("--roles", state->roles,
                  "ray-cast only these roles, e.g. target,environment "
                  "(the orbit stays that of the whole scene)");
    c->add_option("--altitude-m", orbit.altitude_m, "drone altitude above C, metres > 0")->capture_default_str();
    c->add_option("--overlap-m", orbit.overlap_m, "CO: how far past C the footprint reaches, metres")
        ->capture_default_str();
    c->add_option("--alpha-deg", orbit.inclination_deg,
                  "sensor inclination from the vertical, [0, 90) deg; "
                  "alpha + fov/2 < 89.99")
        ->capture_default_str();
    c->add_option("--fov-deg", orbit.fov_deg, "vertical field of view, (0, 170] deg")->capture_default_str();
    c->add_option("--xres", orbit.xres, "pixels across, 1..65536")->capture_default_str();
    c->add_option("--yres", orbit.yres, "pixels down, 1..65536")->capture_default_str();
    c->add_option("--views", orbit.views, "NoV: drone positions on the orbit, 1..65535")->capture_default_str();
    c->add_option("--centre", state->centre,
                  "C as x,y,z world metres; default: the target's centre on the "
                  "ground");
    c->add_option("--threads", o.threads, "worker threads, 0 = all cores")->capture_default_str();
    c->add_option("--seed", o.seed, "RANSAC seed (view v shuffles with mt19937_64(seed ^ v))")->capture_default_str();
    addGroundOptions(*c, state->ground, o.ground);
    c->add_option("--colours", o.colour.entries, "entries of the jet map, [2, 256]")->capture_default_str();
    c->add_option("--memory-mb", state->memory_mb,
                  "bound on the generator's buffers (batches, tiles, threads are planned to fit; "
                  "the fused cloud is spooled to disk when it does not)")
        ->capture_default_str();
    c->add_flag("--json", state->json, "print a JSON summary on stdout");
    addSensorOptions(*c, o.sensor);
    c->callback([state] { run(*state); });
}

}  // namespace app
