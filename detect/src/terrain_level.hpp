// detect/src/terrain_level.hpp (internal): the segmentation's step 1b
// (detect/segmentation.hpp), the terrain levelled on the ground's own points. Within each
// square of the grid, the heights above the terrain between kLevelLow_m and kLevelHigh_m
// are binned in kLevelBin_m bins; the fullest three neighbouring bins are the ground's
// level there (a vehicle's or a shrub's points spread over heights, the ground's gather
// within a few sigmas), their points' mean height the square's offset. A square with
// fewer than kLevelMinPoints such points takes its levelled neighbours' mean, ring by
// ring. Each point's height loses the offset interpolated bilinearly between the
// squares' centres. Where the terrain fit runs through the ground (the ideal sensor, most
// presets' clouds) the offsets are a few centimetres; where it passes under a patch of
// misregistered views (a sparse orbit under a preset), the ground there no longer stands
// half a metre above it and joins no vehicle into one sheet of ground.
#pragma once
#include <core/point_cloud.hpp>

#include <cstddef>
#include <vector>

namespace detect::detail {

inline constexpr double kLevelLow_m = -1.0, kLevelHigh_m = 1.25, kLevelBin_m = 0.05;
inline constexpr std::size_t kLevelMinPoints = 32;
/// The grid has at most 128 squares a side (a cloud over a kilometre wide gets larger
/// squares), so its tables hold at most 9 MB, within BoostedDetector::memoryBytes's
/// fixed part.
inline constexpr double kLevelMaxSquares = 128.0;

/// Levels `height_m` (one per point of `cloud`, above its fitted terrain) in squares of
/// `level_cell_m` (> 0; larger where the cloud spans more than kLevelMaxSquares of them).
void levelTerrain(const core::PointCloud& cloud, double level_cell_m, std::vector<float>& height_m);

}  // namespace detect::detail
