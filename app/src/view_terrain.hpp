// app/src/view_terrain.hpp: the ground under a cloud file that `view` shows, so that
// `--colour above-ground` (and the C key's turn to it) works on a cloud whose points do not
// carry their height above ground. A thread reads an even sample of the file (every k-th
// point of a streamed file, the top levels of a COPC file), builds the ground grid from
// its class 2 points when it has them, else fits SMRF to the sample with `ladarvr
// ground`'s defaults in the file's units, and publishes the grid to the viewer's
// TerrainFeed (viewer/terrain_feed.hpp). `study` starts the same thread for each cloud
// trial shown in above-ground colours (and its replay). docs/view-real-surveys.md.
#pragma once
#include <core/point_cloud.hpp>
#include <sim/ground.hpp>
#include <sim/ground_units.hpp>
#include <viewer/terrain_feed.hpp>

#include <atomic>
#include <cstddef>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <thread>

namespace app {

/// The most points the terrain is built from (about 80 MiB while they are held).
inline constexpr std::size_t kTerrainMostPoints = 2000000;
/// The most cells of the terrain grid; a wider cloud gets coarser cells.
inline constexpr std::size_t kTerrainMostCells = 4000000;
/// Fewer ground points than this in the sample: the terrain is fitted instead.
inline constexpr std::size_t kTerrainLeastGroundPoints = 16;

/// The ground grid of the points labelled ground among `points` (a LAS file's class 2, as
/// the readers give it), in world coordinates (positions + `origin`): the mean height of
/// the ground points in each cell, a cell without any taking the height of the nearest
/// cell that has some. The cell is twice the ground points' mean spacing, at least
/// `least_cell` (file units), and coarser where the grid would pass `max_cells`. Its
/// source names the ground points used. Empty (nx == 0) when no point is ground.
viewer::ViewTerrain groundGrid(std::span<const core::CloudPoint> points, const glm::dvec3& origin, double least_cell,
                               std::size_t max_cells = kTerrainMostCells);

/// How many of `points` are labelled ground.
std::size_t groundPointCount(std::span<const core::CloudPoint> points);

/// SMRF (`ladarvr ground`'s defaults, `units` converting them) fitted to `points`, as a
/// grid in world coordinates, its cell made coarser where the grid would pass `max_cells`.
/// Throws core::Error as the filter does; an empty result when `points` is empty.
viewer::ViewTerrain fittedGrid(std::span<const core::CloudPoint> points, const glm::dvec3& origin,
                               const sim::CoordinateUnits& units, std::size_t max_cells = kTerrainMostCells);

/// An even sample of at most `most_points` of `file`'s points (any cloud the readers read;
/// COPC: the nodes of its top levels), in its reader's frame. Stops early, returning what it
/// has, once `stop` is set. Throws core::Error as the readers do.
core::PointCloud readTerrainSample(const std::filesystem::path& file, std::size_t most_points,
                                   const std::atomic<bool>& stop);

/// Whether `file`'s points carry their height above ground (its header declares the
/// field): then the viewer needs no terrain. False for a file whose header does not read.
bool carriesHeightAboveGround(const std::filesystem::path& file);

/// The thread that builds the terrain of the file the viewer reads (the cloud itself, or
/// its COPC index) and publishes it, or its failure, to `feed`. `what` names the cloud in
/// the source ("the file's", "the survey's"). The destructor asks it to stop and joins it,
/// so it ends with the view, however the view ends.
class TerrainProducer {
  public:
    TerrainProducer(std::filesystem::path file, sim::CoordinateUnits units, std::string what,
                    std::shared_ptr<viewer::TerrainFeed> feed);
    ~TerrainProducer();
    TerrainProducer(const TerrainProducer&) = delete;
    TerrainProducer& operator=(const TerrainProducer&) = delete;

  private:
    std::atomic<bool> stop_{false};
    std::thread thread_;
};

/// A cloud's terrain as it starts: the feed (null: none needed) and its producer (null:
/// none runs).
struct StartedTerrain {
    std::shared_ptr<viewer::TerrainFeed> feed;
    std::unique_ptr<TerrainProducer> producer;
};

/// The ground under `cloud` for above-ground colours, built from `read` (the file the
/// viewer reads: the cloud itself or its index) by a TerrainProducer into a new feed,
/// unless the cloud's points carry their height above ground (then both are null). A
/// cloud whose units cannot take lengths in metres gets the feed's failure at once, with
/// no producer; `context` ("view", "study") is the command the units' errors would name,
/// left out of the failure (the viewer says it after its own "view: no terrain ...").
StartedTerrain startCloudTerrain(const std::filesystem::path& cloud, const std::filesystem::path& read,
                                 const std::string& what, const std::string& context);

}  // namespace app
