// sim/src/scene_from_cloud_internal.hpp: what the conversion's files share: the vehicle's
// placement on the terrain among the boxes (scene_from_cloud_vehicle.cpp) and the OBJ text
// of a vehicle written rather than copied (scene_from_cloud_write.cpp).
#pragma once
#include <sim/scene_from_cloud.hpp>

#include <io/scene_file.hpp>

#include <string>

namespace sim::detail {

/// The vehicle's triangles `m`, read from `mesh`, as OBJ text (z up, every digit a float
/// holds), for a vehicle written rather than copied (vehicleAsObj). Throws core::Error
/// (`where`: ...) for a mesh whose text would pass the 64 MiB a copied mesh may take.
std::string vehicleObj(const io::MeshTriangles& m, const std::filesystem::path& mesh, const std::string& where);

/// Places o.mesh on `terrain` (local frame) at a spot whose fitted plane is flat enough
/// and smooth enough and where no box (sorted, voxel_m) rises within the clearance of its
/// footprint below its top; at o.at_world (minus `offset_m`) when given, else at the
/// first of up to kSpotDraws spots drawn with o.seed. Throws core::Error naming the
/// option to change when no spot qualifies.
PlacedVehicle placeVehicle(const TerrainMesh& terrain, const std::vector<std::array<std::int32_t, 3>>& boxes,
                           double voxel_m, const glm::dvec3& offset_m, const VehiclePlacement& o);

inline constexpr int kSpotDraws = 4000;

}  // namespace sim::detail
