// app/src/cmd_ground.cpp: `ladarvr ground IN --out OUT [--method smrf|csf] [--smrf-*|--csf-*]
// [--reclassify] [--json]`: the ground of a cloud we did not generate (a real survey's
// LAS/LAZ, or any cloud we read), classified by a whole-cloud filter (sim/ground_file.hpp)
// and written to OUT with every ground point labelled ground (LAS class 2); a LAS/LAZ/COPC
// input keeps its other classes and every other field it carries. Options are parsed and checked
// here; the work is sim::classifyGroundFile. The defaults are the set tuned on the ISPRS
// samples (docs/ground.md), not `generate --ground`'s.
#include "cli_common.hpp"
#include "commands.hpp"
#include "ground_options.hpp"

#include <core/error.hpp>
#include <io/cloud_io.hpp>
#include <io/cloud_reader.hpp>
#include <io/copc_writer.hpp>
#include <platform/atomic_file.hpp>
#include <platform/input_set.hpp>
#include <platform/progress.hpp>
#include <platform/safe_file.hpp>
#include <sim/ground_file.hpp>
#include <sim/ground_units.hpp>
#include <sim/memory_budget.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

namespace app {
namespace {

// What the terrain raster holds per cell while it is gathered and fitted: the lowest
// heights with their views (100 bytes) and the fit's working rasters.
constexpr std::uint64_t kBytesPerCell = 160;

struct GroundFileCli {
    std::string in, out;
    std::string method = "smrf";
    sim::GroundFileOptions options;
    double low_outlier_m = sim::kSurveyLowOutlier_m;
    double memory_mb = 1024.0;
    bool json = false;
};

void run(GroundFileCli& cli) {
    const auto t0 = std::chrono::steady_clock::now();
    cli.options.method = sim::parseGroundMethod(cli.method, "ground: --method");
    if (cli.options.method == sim::GroundMethod::Ransac)
        throw core::Error("ground: --method ransac: RANSAC works per view of a generated cloud; allowed smrf, csf");
    cli.options.smrf.low_outlier_m = cli.options.csf.low_outlier_m = cli.low_outlier_m;
    sim::validate(cli.options);
    const std::uint64_t budget = sim::memoryBudgetBytes(cli.memory_mb, "ground");
    platform::checkDistinctPaths("ground", {{"input", cli.in, platform::PathRole::Input, {}},
                                            {"--out", cli.out, platform::PathRole::Output, {}}});
    platform::checkInputFile(cli.in, "ground: input " + core::printable(cli.in, 400));
    platform::InputSet inputs;
    inputs.addFile(cli.in);
    const std::filesystem::path out = cli.out;
    const io::CloudFormat format = io::formatForPath(out, "ground: --out");

    // The memory: the reader's two chunks, the writer's share, the rest for the raster.
    const std::uint64_t reading = 2 * io::CloudReader::kChunkPoints * sizeof(core::CloudPoint);
    io::LasOptions las;
    io::CopcOptions copc;
    std::uint64_t writing = 2 * io::lazChunkBytes();
    if (format == io::CloudFormat::Copc) {
        writing = std::max<std::uint64_t>(io::copcMinimumBytes(0), budget > reading ? (budget - reading) / 2 : 0);
        copc.memory_bytes = writing;
    }
    const std::uint64_t least = reading + writing + 1024 * kBytesPerCell;
    sim::refuseOverBudget("ground", budget, least, "two chunks of points read, the writer's buffers and a raster",
                          "raise --memory-mb");
    const std::size_t max_cells = std::size_t((budget - reading - writing) / kBytesPerCell);

    std::size_t declared = 0;
    {
        const io::CloudReader reader(cli.in);  // the header checked before the output is touched
        declared = reader.declaredPoints();
    }
    const sim::CoordinateUnits units = sim::readCoordinateUnits(cli.in, "ground");  // options in metres to its units
    if (!units.metres())
        std::fprintf(stderr, "ground: coordinates in %s: options converted\n", sim::describe(units).c_str());
    createParentFolders(out, "ground: --out");
    platform::checkWritableDestination(out, inputs);
    platform::Progress progress("ground: reading twice", 2 * declared);
    const sim::GroundFileStats st = sim::classifyGroundFile(cli.in, out, sim::inUnits(cli.options, units), max_cells,
                                                            las, copc, [&](std::size_t n) { progress.advance(n); });
    progress.finish();
    if (!st.reader_warning.empty()) platform::printMessage("warning", st.reader_warning);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const double share = st.points > 0 ? 100.0 * double(st.ground_points) / double(st.points) : 0.0;
    if (cli.json) {
        nlohmann::json j;
        j["in"] = cli.in;
        j["out"] = cli.out;
        j["method"] = sim::groundMethodName(cli.options.method);
        j["options"] = sim::describe(cli.options);
        j["points"] = st.points;
        j["ground_points"] = st.ground_points;
        j["input_ground_points"] = st.was_ground;
        j["input_ground_points_kept"] = st.still_ground;
        j["raster"] = {{"nx", st.nx}, {"ny", st.ny}, {"cell_m", st.cell_m * units.horizontal_m}};
        j["seconds"] = seconds;
        std::printf("%s\n", j.dump(2).c_str());
        return;
    }
    std::printf("ground: wrote %s: %zu points, %zu ground (%.2f %%), %s, raster %d x %d, %.3f s\n",
                platform::messageLine(cli.out, 400).c_str(), st.points, st.ground_points, share,
                sim::describe(cli.options).c_str(), st.nx, st.ny, seconds);
}

}  // namespace

void registerGround(CLI::App& cli) {
    auto state = std::make_shared<GroundFileCli>();
    CLI::App* c = cli.add_subcommand(
        "ground",
        "classify the ground of a cloud (a real survey's LAS/LAZ, or PCD, PLY, COPC) with a whole-cloud filter "
        "and write it with every point labelled ground (LAS class 2) or not (class 1)");
    c->add_option("in", state->in, "the input cloud; it is never overwritten")->required();
    c->add_option("--out", state->out,
                  "the cloud to write; its name gives the format (.las, .laz, .copc.laz, .pcd, "
                  ".ply)")
        ->required();
    c->add_option("--method", state->method,
                  "smrf (Pingel et al. 2013, the default: the best on the ISPRS samples with one parameter set) or "
                  "csf (Zhang et al. 2016)")
        ->capture_default_str();
    addSmrfOptions(*c, state->options.smrf);
    addCsfOptions(*c, state->options.csf);
    c->add_option("--low-outlier-m", state->low_outlier_m,
                  "a return this far below the ground around it (multipath, noise) is left out of the terrain and is "
                  "not ground, metres [0, 1000], 0 = keep every return")
        ->capture_default_str();
    c->add_option("--memory-mb", state->memory_mb, "bound on memory: the terrain raster and the points in flight")
        ->capture_default_str();
    c->add_flag("--reclassify", state->options.reclassify,
                "a LAS/LAZ/COPC input's points that are not ground all become class 1 (by default its classes other "
                "than ground are kept)");
    c->add_flag("--json", state->json, "print the run's figures as JSON on stdout");
    c->callback([state] { run(*state); });
}

}  // namespace app
