// sim/src/terrain_stage.hpp: the generator's terrain stage, a terrain fitted to the
// whole fused cloud in two streamed passes. Pass 1 (add) sees the fused points as they
// are emitted (into memory or the spool file), fit() builds the terrain, pass 2
// (classify) runs on each chunk before it is coloured. With a whole-cloud filter it
// whitens the ground and fills height above ground; with the paper's per-view RANSAC it
// fits SMRF's terrain only to check RANSAC's result (how many points on the terrain were
// left coloured, counted on every 8th point), and changes no point.
#pragma once
#include "parallel.hpp"

#include <sim/generator.hpp>

#include <chrono>
#include <memory>
#include <span>
#include <vector>

namespace sim {

/// With a whole-cloud filter, the points within this height of its terrain are counted
/// (GenerateStats::terrain_points) with those it left coloured, to warn when the ground
/// is thicker than the filter's tolerance.
inline constexpr double kNearTerrain_m = 1.0;

class TerrainStage {
  public:
    /// `filter`: the whole-cloud filter that whitens, or null with a per-view filter; then
    /// `check` fits SMRF with `check_options` to check its result (no effect on points).
    /// `white`: no ground stage at all.
    TerrainStage(const CloudGroundFilter* filter, const SmrfOptions& check_options, bool white, bool check = true);
    /// Whether pass 2 changes points (a whole-cloud filter ran): the cloud then carries
    /// height above ground.
    bool whitens() const { return whitens_; }
    void add(std::span<const core::CloudPoint> points);
    void fit();
    void classify(std::span<core::CloudPoint> points, Workers& pool);
    /// Into `st`: the counts of pass 2, precision and recall, the terrain, the seconds
    /// (pass 1 ran inside the fuse stage's clock: its time moves from fuse to ground).
    void finish(GenerateStats& st);

  private:
    std::unique_ptr<TerrainFit> fit_;
    bool whitens_ = false;
    bool failed_ = false;  // the check's fit could not grid the cloud: no check
    double seconds_ = 0, add_seconds_ = 0;
    std::uint64_t found_ = 0, true_positive_ = 0, terrain_ = 0, terrain_coloured_ = 0;
    // The check of a per-view filter fits and counts every kCheckStride-th point of the
    // cloud (by its rank, whatever the chunks): the minimum surface is as good at that
    // density, and it keeps the check cheap next to RANSAC.
    static constexpr std::size_t kCheckStride = 8;
    std::size_t added_ = 0, classified_ = 0;  // points seen by add(), classify()
    std::vector<core::CloudPoint> sample_;
};

}  // namespace sim
