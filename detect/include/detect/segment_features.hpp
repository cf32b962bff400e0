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
#include <span>
#include <string>
#include <vector>

namespace detect {

/// The feature names, in the order segmentFeatures() returns them. A model file records
/// this list; a model trained on another list is refused.
const std::vector<std::string>& segmentFeatureNames();

/// The features of one segment: `points` (ascending indices, not empty) of `cloud`,
/// `height_m` each point's height above the terrain (one per cloud point),
/// `target_size_m` the size class (length, width, height) the size match is scored
/// against. Returns segmentFeatureNames().size() values.
std::vector<float> segmentFeatures(const core::PointCloud& cloud, std::span<const std::uint32_t> points,
                                   std::span<const float> height_m, const glm::dvec3& target_size_m);

}  // namespace detect
