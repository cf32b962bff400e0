// detect/segment_features.hpp: what the trained detector knows of a segment, a fixed list
// of numbers per segment. The shape features are the eigenvalue features of Weinmann et
// al. (2015, "Semantic point cloud interpretation based on optimal neighborhoods...",
// linearity, planarity, scattering, verticality) taken over the whole segment, as
// segment-based classifiers do (Golovinskiy, Kim, Funkhouser 2009, "Shape-based
// recognition of 3D point clouds in urban environments": size, height profile, density);
// the box size and its match to the target's size are the baseline detector's. A feature
// a cloud cannot give (intensity without an intensity field, returns without return
// numbers) is NaN, which the trees treat as missing.
#pragma once
#include <core/point_cloud.hpp>

#include <glm/glm.hpp>

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace detect {

/// The feature lists a model may name. kV1 is the list models were first trained on (the
/// shipped model's): sizes, heights, eigenvalue shapes, profile, fill, returns. kV2 adds,
/// after those, features of "a vehicle" rather than of the vehicles seen: the box's
/// proportions, heights as shares of the segment's top, the height profile along the
/// long axis and across it, how flat and how covered the top is, the share of points in
/// side and end walls, the box's fill on a grid scaled to the box, and the point count
/// and density over the cloud's own density (so the same shape sampled by another sensor
/// or orbit gives the same numbers).
enum class FeatureSet { kV1 = 1, kV2 = 2 };
/// What `ladarvr train` learns on.
inline constexpr FeatureSet kCurrentFeatures = FeatureSet::kV2;

/// The feature names of `set`, in the order segmentFeatures() returns them. A model file
/// records this list; a model whose list is no known set is refused.
const std::vector<std::string>& segmentFeatureNames(FeatureSet set = kCurrentFeatures);
/// The set whose names are exactly `names`, if any.
std::optional<FeatureSet> featureSetOf(const std::vector<std::string>& names);

/// The features of one segment: `points` (ascending indices, not empty) of `cloud`,
/// `height_m` each point's height above the terrain (one per cloud point),
/// `target_size_m` the size class (length, width, height) the size match is scored
/// against, `density_m2` the cloud's points per square metre of observed terrain (0:
/// unknown, the relative features are then missing). Returns
/// segmentFeatureNames(set).size() values; a set's values are the same whatever later
/// sets add.
std::vector<float> segmentFeatures(const core::PointCloud& cloud, std::span<const std::uint32_t> points,
                                   std::span<const float> height_m, const glm::dvec3& target_size_m,
                                   FeatureSet set = kCurrentFeatures, double density_m2 = 0.0);

}  // namespace detect
