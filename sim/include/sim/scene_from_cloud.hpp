// sim/scene_from_cloud.hpp: a real survey (LAS/LAZ/COPC, or any cloud io::CloudReader
// reads) turned into a scene the generator flies over (`ladarvr scene from-cloud`): its
// ground (class 2 where the file has it, else `ladarvr ground`'s filter) as a terrain mesh
// on a regular grid, its other points as axis-aligned voxel boxes (the way HELIOS++ turns
// point-cloud scene parts into geometry), both in a local frame near (0, 0) whose offset
// from the survey's coordinates is recorded, and a vehicle mesh placed on a flat, free
// spot of that ground as the target. The file is read in chunks (two or three passes):
// the memory is the terrain grid and the set of occupied voxels, each bounded.
#pragma once
#include <sim/ground_file.hpp>
#include <sim/ground_units.hpp>

#include <glm/glm.hpp>

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace sim {

/// Where the ground comes from.
enum class SceneGroundSource {
    Auto,     // the file's class-2 points when at least 1 % of its points are class 2, else the filter
    Classes,  // the file's class-2 points (refused when it has none)
    Filter,   // GroundFileOptions' filter, whatever classes the file holds
};

/// The vehicle put on the ground as the scene's target.
struct VehiclePlacement {
    std::filesystem::path mesh;  // a mesh file Assimp reads; empty: no vehicle
    bool up_y = false;           // the mesh's up axis is y (glTF's), else z
    /// Where its centre goes, in the survey's coordinates (metres; feet files converted);
    /// unset: a random flat, free spot drawn with `seed`.
    std::optional<glm::dvec2> at_world;
    std::optional<double> yaw_deg;  // unset: drawn with `seed`
    double max_slope = 0.15;        // the plane fitted to the ground under it: rise over run
    double max_roughness_m = 0.3;   // the ground under it at most this far off that plane
    double clearance_m = 1.0;       // no box within this of its footprint, up to its height + this
    std::uint64_t seed = 1;
};

/// Every option of the conversion; validate() checks them once at the boundary.
struct SceneFromCloudOptions {
    double voxel_m = 0.5;             // the boxes' edge, (0.05, 100] m
    double cell_m = 0.0;              // the terrain grid's spacing; 0: from the ground points' spacing
    std::size_t max_boxes = 500000;   // boxes written at most
    bool coarsen = false;             // past max_boxes: double the voxel until they fit (else refuse)
    std::size_t max_cells = 4000000;  // terrain grid nodes at most
    /// Points more than this above the terrain (birds, noise) or kSurveyLowOutlier_m below
    /// it make no box.
    double max_height_m = 150.0;
    SceneGroundSource ground_source = SceneGroundSource::Auto;
    GroundFileOptions ground;  // the filter, in metres
    VehiclePlacement vehicle;
};

/// Throws core::Error("scene from-cloud: --<option> ...") naming the option and its range.
void validate(const SceneFromCloudOptions& o);

/// The terrain: heights at the nodes of a regular grid (node (i, j) at x0 + i * cell,
/// y0 + j * cell, local frame), each the mean height of the ground points nearest it, the
/// nodes without any filled from their neighbours; triangulated two triangles a cell,
/// split along the diagonal from (i, j) to (i + 1, j + 1).
struct TerrainMesh {
    double x0_m = 0, y0_m = 0, cell_m = 1;
    int nx = 0, ny = 0;
    std::vector<float> z_m;          // nx * ny, row j after row j - 1
    std::size_t observed_nodes = 0;  // nodes that had ground points
    float at(int i, int j) const { return z_m[std::size_t(j) * std::size_t(nx) + std::size_t(i)]; }
    /// The mesh's height at (x, y) (local), on the triangle that holds it; outside the
    /// grid, at the nearest point of its edge.
    double heightAt(double x, double y) const;
};

/// The vehicle as placed: the scene entry's transform and what was measured.
struct PlacedVehicle {
    std::string file;          // its name in the scene folder (vehicleFileName)
    std::string obj_text;      // where vehicleAsObj: the file's text, from the one import of the mesh
    glm::dvec3 position{0.0};  // the entry's position, local frame
    double yaw_deg = 0, pitch_deg = 0, roll_deg = 0;
    glm::dvec3 size_m{0.0};            // its mesh's bounding box
    glm::dvec3 footprint_centre{0.0};  // the bottom centre, local frame: on the ground
    double slope = 0;                  // of the plane under it
    double roughness_m = 0;            // the ground's largest distance from that plane under it
    int attempts = 0;                  // spots drawn before this one was taken
};

/// The scene in memory before it is written.
struct SceneFromCloud {
    std::filesystem::path survey;
    glm::dvec3 offset_m{0.0};  // local = survey coordinates (metres) - offset_m
    CoordinateUnits units;     // the survey's; converted to metres
    std::size_t points = 0, ground_points = 0;
    std::size_t dropped_high = 0, dropped_low = 0;  // outliers that made no box
    std::string ground_from;                        // "class 2" or the filter's describe()
    TerrainMesh terrain;
    double voxel_m = 0, voxel_requested_m = 0;       // differ when coarsened
    std::vector<std::array<std::int32_t, 3>> boxes;  // occupied voxels (i, j, k), box [i, i+1) * voxel_m..., sorted
    std::string reader_warning;
    std::optional<PlacedVehicle> vehicle;
};

/// Reads `survey` and builds the scene. `progress(points)` is called as points are read
/// (each pass). Throws core::Error("scene from-cloud: ...") in one line for: a file with
/// no points, a geographic CRS or a unit of unknown length (sim::coordinateUnits), a
/// grid past max_cells (naming --cell-m), more boxes than max_boxes without `coarsen`
/// (naming --voxel-m, --max-boxes and --coarsen), Classes asked of a file with no class
/// 2, no flat, free spot for the vehicle, a vehicle mesh that cannot be read.
SceneFromCloud buildSceneFromCloud(const std::filesystem::path& survey, const SceneFromCloudOptions& o,
                                   const std::function<void(std::size_t)>& progress);

/// The OBJ text of the terrain (role ground) and of the boxes (role environment, one
/// box a voxel, a face left out where the next voxel is occupied too).
std::string terrainObj(const TerrainMesh& t);
std::string boxesObj(const std::vector<std::array<std::int32_t, 3>>& boxes, double voxel_m);
/// The vehicle's name in the scene folder: "target" + the mesh's extension where the mesh
/// is copied as it is; "target.obj", its triangles written z up, where a copy would not
/// do: a .gltf (its buffers are other files) or a mesh whose up axis is y.
std::string vehicleFileName(const VehiclePlacement& v);
/// Whether the vehicle is written as OBJ rather than copied (vehicleFileName).
bool vehicleAsObj(const VehiclePlacement& v);

/// The scene file's JSON (ground.obj, environment.obj when there are boxes, the vehicle
/// as the target) and the record of the conversion (from_cloud.json).
std::string sceneJson(const SceneFromCloud& s);
std::string recordJson(const SceneFromCloud& s, const SceneFromCloudOptions& o);

/// The names a scene folder holds (AtomicFolder's OwnedName).
bool isSceneFromCloudFile(const std::string& name);

/// Writes the folder `dir` as a whole (platform::AtomicFolder): scene.json, ground.obj,
/// environment.obj, the vehicle's mesh copied as s.vehicle->file, from_cloud.json.
/// The caller checks that `dir` is no input. Throws core::Error("output: ...").
void writeSceneFolder(const std::filesystem::path& dir, const SceneFromCloud& s, const SceneFromCloudOptions& o);

}  // namespace sim
