// app/src/ground_options.cpp: see ground_options.hpp.
#include "ground_options.hpp"

#include "cli_common.hpp"

#include <core/error.hpp>
#include <platform/atomic_file.hpp>
#include <sim/dtm.hpp>

#include <nlohmann/json.hpp>

#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

namespace app {

namespace {
constexpr double kMinRecall = 0.80;           // labelled ground whitened, below which we advise
constexpr double kMaxColouredTerrain = 0.20;  // share of terrain points left coloured, above which

std::string percentText(double v) {
    char b[32];
    std::snprintf(b, sizeof b, "%.1f %%", 100.0 * v);
    return b;
}
}  // namespace

void addRansacOptions(CLI::App& c, sim::RansacOptions& ransac) {
    c.add_option("--band-m", ransac.band_m, "RANSAC band above each view's lowest point, metres > 0")
        ->capture_default_str();
    c.add_option("--ransac-distance-m", ransac.distance_threshold_m, "RANSAC inlier distance, metres > 0")
        ->capture_default_str();
    c.add_option("--min-normal-z", ransac.min_normal_z, "accept planes with |normal.z| >= this, [0, 1]")
        ->capture_default_str();
    c.add_option("--stop-fraction", ransac.stop_fraction,
                 "stop when PC is under this fraction of the band, "
                 "[0, 1]")
        ->capture_default_str();
    c.add_option("--min-plane-fraction", ransac.min_plane_fraction,
                 "a ground plane holds at least this fraction of the band, [0, 1]; 0 = the paper's rule")
        ->capture_default_str();
    c.add_option("--max-planes", ransac.max_planes, "planes per view at most, [0, 100000]")->capture_default_str();
    c.add_option("--ransac-iterations", ransac.ransac_iterations, "RANSAC iterations per plane at most")
        ->capture_default_str();
    c.add_option("--ransac-sample-points", ransac.ransac_sample_points,
                 "RANSAC searches planes on at most this many band points, 0 = all")
        ->capture_default_str();
}

void addSmrfOptions(CLI::App& c, sim::SmrfOptions& smrf) {
    c.add_option("--smrf-cell-m", smrf.cell_m, "SMRF cell of the minimum surface and the DTM, metres [0.01, 1000]")
        ->capture_default_str();
    c.add_option("--smrf-slope", smrf.slope, "SMRF slope threshold, rise over run (0, 100]")->capture_default_str();
    c.add_option("--smrf-window-m", smrf.window_m, "SMRF largest opening radius, metres > 0")->capture_default_str();
    c.add_option("--smrf-threshold-m", smrf.threshold_m,
                 "SMRF: ground within this height of the terrain, metres [0, 1000]")
        ->capture_default_str();
    c.add_option("--smrf-scalar", smrf.scalar, "SMRF: plus this many metres per unit of terrain slope, [0, 1000]")
        ->capture_default_str();
}

void addCsfOptions(CLI::App& c, sim::CsfOptions& csf) {
    c.add_option("--csf-cloth-m", csf.cloth_m, "CSF cloth resolution (particle spacing, DTM cell), metres [0.01, 1000]")
        ->capture_default_str();
    c.add_option("--csf-rigidness", csf.rigidness, "CSF cloth rigidness: 1 steep terrain .. 3 flat")
        ->capture_default_str();
    c.add_option("--csf-threshold-m", csf.threshold_m, "CSF: ground within this height of the cloth, metres")
        ->capture_default_str();
    c.add_option("--csf-time-step", csf.time_step, "CSF simulation time step, (0, 10]")->capture_default_str();
    c.add_option("--csf-iterations", csf.iterations, "CSF simulation steps at most, [1, 100000]")
        ->capture_default_str();
}

void addGroundOptions(CLI::App& c, GroundCli& cli, sim::GroundChoice& ground) {
    addRansacOptions(c, ground.ransac);
    c.add_option("--ground", cli.method,
                 "ground filter: ransac (paper §III-C, per view; flat ground), smrf (Pingel et al. 2013) or csf "
                 "(Zhang et al. 2016; both on the whole cloud, following sloped terrain)")
        ->capture_default_str();
    addSmrfOptions(c, ground.smrf);
    addCsfOptions(c, ground.csf);
    c.add_option("--dtm", cli.dtm,
                 "also write the fitted terrain (SMRF's or CSF's surface; SMRF's with --ground ransac) as an "
                 "ESRI ASCII grid (.asc) or a GeoTIFF (.tif, .tiff), world metres");
}

bool isGeoTiffName(const std::filesystem::path& dtm) {
    std::string ext = dtm.extension().string();
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    return ext == ".tif" || ext == ".tiff";
}

void checkDtmName(const std::string& dtm, const char* command) {
    std::string ext = std::filesystem::path(dtm).extension().string();
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    if (ext != ".asc" && !isGeoTiffName(dtm))
        throw core::Error(std::string(command) + ": --dtm " + core::printable(dtm, 400) +
                          ": allowed a name ending in .asc (an ESRI ASCII grid) or .tif, .tiff (a GeoTIFF)");
}

void applyGroundOptions(const GroundCli& cli, sim::GenerateOptions& o) {
    o.ground.method = sim::parseGroundMethod(cli.method, "generate: --ground");
    o.fit_terrain = !cli.dtm.empty();
    if (!cli.dtm.empty()) {
        if (o.white)
            throw core::Error("generate: --dtm: not with --white (no ground filter runs, no terrain is fitted)");
        checkDtmName(cli.dtm, "generate");
    }
}

void prepareDtmOutput(const GroundCli& cli) {
    if (cli.dtm.empty()) return;
    createParentFolders(cli.dtm, "generate: --dtm");
    platform::checkWritableDestination(cli.dtm);
}

std::unique_ptr<platform::TempFile> stageDtm(const GroundCli& cli, const sim::GenerateStats& st,
                                             const glm::dvec3& origin) {
    if (cli.dtm.empty()) return nullptr;
    const std::string out = "output: " + core::printable(cli.dtm, 400) + ": ";
    if (!st.terrain || st.terrain->empty())
        throw core::Error(out + "no terrain was fitted (--white, or an empty cloud)");
    auto file = std::make_unique<platform::TempFile>(cli.dtm);
    if (isGeoTiffName(cli.dtm)) {
        // A generated cloud has no CRS: the grid is placed, without keys.
        sim::dtmGeoTiff(file->file(), *st.terrain, origin, {}, core::printable(cli.dtm, 400));
        return file;
    }
    const std::string text = sim::dtmAscii(*st.terrain, origin);
    if (std::fwrite(text.data(), 1, text.size(), file->file()) != text.size() || std::fflush(file->file()) != 0)
        throw core::Error(out + "write failed: " + std::strerror(errno));
    return file;
}

std::optional<std::string> groundAdvice(const sim::GenerateStats& st) {
    // What to try, per method.
    std::string name, next;
    switch (st.ground_method) {
        case sim::GroundMethod::Ransac:
            name = "RANSAC";
            next = " (the terrain is not flat); --ground smrf or --ground csf follows sloped terrain";
            break;
        case sim::GroundMethod::Smrf:
            name = "SMRF";
            next =
                " (the ground is thicker or rougher than its tolerance); raise --smrf-threshold-m, or try --ground csf";
            break;
        case sim::GroundMethod::Csf:
            name = "CSF";
            next =
                " (the ground is thicker or steeper than its tolerance); raise --csf-threshold-m, lower "
                "--csf-rigidness on steep terrain, or try --ground smrf";
            break;
    }
    if (st.ground_truth > 0 && st.ground_recall) {
        if (*st.ground_recall >= kMinRecall) return std::nullopt;
        return "generate: ground: " + name + " whitened only " + percentText(*st.ground_recall) +
               " of the ground-labelled points" + next;
    }
    if (st.ground_truth == 0 && st.terrain_points > 0) {
        const double share = double(st.terrain_points_coloured) / double(st.terrain_points);
        if (share <= kMaxColouredTerrain) return std::nullopt;
        return "generate: ground: " + name + " left " + percentText(share) + " of the points " +
               (st.ground_method == sim::GroundMethod::Ransac ? "on the fitted terrain"
                                                              : "within 1 m of its fitted terrain") +
               " coloured" + next;
    }
    return std::nullopt;
}

std::string groundFoundText(const sim::GenerateOptions& o, const sim::GenerateStats& st) {
    if (o.white) return "no filter ran (--white)";
    const std::string found = std::to_string(st.ground_found) + " points ";
    switch (st.ground_method) {
        case sim::GroundMethod::Ransac:
            return found + "whitened by RANSAC (" + std::to_string(st.planes_accepted) + " planes kept, " +
                   std::to_string(st.planes_rejected) + " dropped)";
        case sim::GroundMethod::Smrf: return found + "found on SMRF's terrain and whitened";
        case sim::GroundMethod::Csf: return found + "found on CSF's cloth and whitened";
    }
    return found + "whitened";
}

void reportGround(const GroundCli& cli, const sim::GenerateOptions& o, const sim::GenerateStats& st) {
    if (!o.white && o.ground.method == sim::GroundMethod::Csf)
        std::fprintf(stderr,
                     "  ground filter: csf (cloth %g m, rigidness %d, threshold %g m, time step %g, %d iterations), "
                     "terrain %d x %d cells, %.3f s\n",
                     o.ground.csf.cloth_m, o.ground.csf.rigidness, o.ground.csf.threshold_m, o.ground.csf.time_step,
                     o.ground.csf.iterations, st.terrain ? st.terrain->nx : 0, st.terrain ? st.terrain->ny : 0,
                     st.seconds.ground);
    if (!o.white && o.ground.method == sim::GroundMethod::Smrf)
        std::fprintf(stderr,
                     "  ground filter: smrf (cell %g m, slope %g, window %g m, threshold %g m, scalar %g), "
                     "terrain %d x %d cells, %.3f s\n",
                     o.ground.smrf.cell_m, o.ground.smrf.slope, o.ground.smrf.window_m, o.ground.smrf.threshold_m,
                     o.ground.smrf.scalar, st.terrain ? st.terrain->nx : 0, st.terrain ? st.terrain->ny : 0,
                     st.seconds.ground);
    if (const auto advice = groundAdvice(st)) warn(*advice);
    if (!cli.dtm.empty() && st.terrain) {
        std::fprintf(stderr, "  DTM: %s (%d x %d cells of %g m)\n", cli.dtm.c_str(), st.terrain->nx, st.terrain->ny,
                     st.terrain->cell_m);
    }
}

void addGroundJson(nlohmann::json& j, const GroundCli& cli, const sim::GenerateStats& st) {
    j["ground_method"] = sim::groundMethodName(st.ground_method);
    j["terrain_points"] = st.terrain_points;
    j["terrain_points_coloured"] = st.terrain_points_coloured;
    j["ground_advice"] = groundAdvice(st).value_or("");
    j["ground_thickness_m"] = st.terrain ? st.terrain->ground_sigma_m : 0.0;
    j["ground_thickness_uncorrected_m"] =
        st.terrain ? (st.terrain->views_corrected ? st.terrain->ground_sigma_uncorrected_m : st.terrain->ground_sigma_m)
                   : 0.0;
    j["views_corrected"] = st.terrain ? st.terrain->views_corrected : 0;
    j["dtm"] = cli.dtm.empty() ? nlohmann::json(nullptr) : nlohmann::json(std::filesystem::absolute(cli.dtm).string());
    j["stage_seconds"]["ground_check"] = st.seconds.ground_check;
}

}  // namespace app
