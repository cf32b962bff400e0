// app/src/ground_options.hpp: `ladarvr generate`'s ground filter options (--ground,
// each filter's group: RANSAC's, --smrf-*, --csf-*; --dtm), the line that says when
// RANSAC left the terrain coloured, and the DTM export.
#pragma once
#include <platform/safe_file.hpp>
#include <sim/generator.hpp>

#include <CLI/CLI.hpp>
#include <nlohmann/json_fwd.hpp>

#include <filesystem>
#include <memory>
#include <optional>
#include <string>

namespace app {

struct GroundCli {
    std::string method = "ransac";
    std::string dtm;  // --dtm: ESRI ASCII grid of the fitted terrain; empty: none
};

/// Each filter's own option group: RANSAC's (--band-m, --ransac-distance-m,
/// --min-normal-z, --stop-fraction, --min-plane-fraction, --max-planes,
/// --ransac-iterations, --ransac-sample-points), SMRF's (--smrf-*), CSF's (--csf-*).
void addRansacOptions(CLI::App& command, sim::RansacOptions& ransac);
void addSmrfOptions(CLI::App& command, sim::SmrfOptions& smrf);
void addCsfOptions(CLI::App& command, sim::CsfOptions& csf);

/// Adds every filter's group, --ground (the choice) and --dtm to `generate`.
void addGroundOptions(CLI::App& generate, GroundCli& cli, sim::GroundChoice& ground);

/// Throws core::Error("<command>: --dtm <name>: allowed a name ending in .asc ...") unless
/// `dtm`'s name ends in .asc (an ESRI ASCII grid) or .tif, .tiff (a GeoTIFF), any case.
/// Whether a DTM's name asks for a GeoTIFF (.tif, .tiff, any case) rather than an ESRI
/// ASCII grid.
bool isGeoTiffName(const std::filesystem::path& dtm);

void checkDtmName(const std::string& dtm, const char* command);

/// Before any work: --ground into `o.ground.method`; --dtm refused with --white (no
/// terrain is fitted) and unless its name ends in .asc (the format it is written in).
void applyGroundOptions(const GroundCli& cli, sim::GenerateOptions& o);

/// Before any work, once the run's paths are known to be distinct: --dtm's folders made
/// and its destination checked (platform::checkWritableDestination). Nothing without --dtm.
void prepareDtmOutput(const GroundCli& cli);

/// Called by the generator once the cloud is in its temporary, before it is renamed into
/// place: writes --dtm to a temporary of its own and flushes it, so that a full disk or a
/// bad destination fails the run while the cloud can still be discarded. The caller
/// commits the returned file after the cloud; null without --dtm. Throws core::Error
/// ("output: <dtm>: ...") when no terrain was fitted or the write fails.
std::unique_ptr<platform::TempFile> stageDtm(const GroundCli& cli, const sim::GenerateStats& st,
                                             const glm::dvec3& origin);

/// The one line saying that the per-view RANSAC left much of the ground coloured and
/// naming --ground smrf: when the ground-labelled points' recall is under 80 %, or,
/// without ground labels, when over 20 % of the points on SMRF's fitted terrain stayed
/// coloured. None otherwise (and never for a terrain-following method).
std::optional<std::string> groundAdvice(const sim::GenerateStats& st);

/// What the filter that ran found, for the run's "ground:" summary line, in its own
/// words: "N points whitened by RANSAC (P planes kept, D dropped)" for the per-view
/// RANSAC, "N points found on SMRF's terrain and whitened" (or CSF's cloth) for a
/// terrain-following filter, "no filter ran (--white)" without one.
std::string groundFoundText(const sim::GenerateOptions& o, const sim::GenerateStats& st);

/// After the run: prints the filter's summary line, groundAdvice() and where --dtm went.
void reportGround(const GroundCli& cli, const sim::GenerateOptions& o, const sim::GenerateStats& st);

/// Ground fields of the JSON summary.
void addGroundJson(nlohmann::json& j, const GroundCli& cli, const sim::GenerateStats& st);

}  // namespace app
