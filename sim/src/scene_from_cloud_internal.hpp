// sim/src/scene_from_cloud_internal.hpp: what the conversion's files share: the vehicle's
// placement on the terrain among the boxes (scene_from_cloud_vehicle.cpp).
#pragma once
#include <sim/scene_from_cloud.hpp>

namespace sim::detail {

/// Places o.mesh on `terrain` (local frame) at a spot whose fitted plane is flat enough
/// and smooth enough and where no box (sorted, voxel_m) rises within the clearance of its
/// footprint below its top; at o.at_world (minus `offset_m`) when given, else at the
/// first of up to kSpotDraws spots drawn with o.seed. Throws core::Error naming the
/// option to change when no spot qualifies.
PlacedVehicle placeVehicle(const TerrainMesh& terrain, const std::vector<std::array<std::int32_t, 3>>& boxes,
                           double voxel_m, const glm::dvec3& offset_m, const VehiclePlacement& o);

inline constexpr int kSpotDraws = 4000;

}  // namespace sim::detail
