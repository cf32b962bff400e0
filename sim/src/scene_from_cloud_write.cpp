// sim/src/scene_from_cloud_write.cpp: the files of `scene from-cloud`'s folder: the
// terrain and the boxes as OBJ text, the scene file the generator reads, the record of
// the conversion, all written as one folder (platform::AtomicFolder).
#include <sim/scene_from_cloud.hpp>

#include "scene_from_cloud_internal.hpp"

#include <core/error.hpp>
#include <platform/output_folder.hpp>
#include <platform/safe_file.hpp>

#include <algorithm>
#include <cstdio>
#include <string>

namespace sim {

namespace {

// The largest vehicle mesh file copied into the folder, and the most OBJ text written for one.
constexpr std::size_t kMaxVehicleBytes = std::size_t(64) << 20;

std::string fixed(double v, int decimals) {
    char buffer[64];
    std::snprintf(buffer, sizeof buffer, "%.*f", decimals, v == 0.0 ? 0.0 : v);
    return buffer;
}

std::string triple(const glm::dvec3& v, int decimals) {
    return "[" + fixed(v.x, decimals) + ", " + fixed(v.y, decimals) + ", " + fixed(v.z, decimals) + "]";
}

// A JSON string of printable text (core::printable escapes the rest).
std::string quoted(const std::string& text) {
    std::string out = "\"";
    for (const char c : core::printable(text, 1000)) {
        if (c == '"' || c == '\\') out += '\\';
        out += c;
    }
    return out + "\"";
}

void vertexLine(std::string& out, double x, double y, double z) {
    char buffer[96];
    std::snprintf(buffer, sizeof buffer, "v %.4f %.4f %.4f\n", x, y, z);
    out += buffer;
}

}  // namespace

std::string detail::vehicleObj(const io::MeshTriangles& m, const std::filesystem::path& mesh,
                               const std::string& where) {
    // At most 52 bytes a vertex and 36 a triangle as text: refused before it is made.
    if (m.vertices.size() * 52 + m.triangles.size() * 36 > kMaxVehicleBytes)
        throw core::Error(where + ": " + std::to_string(m.triangles.size()) +
                          " triangles; allowed a vehicle whose OBJ text takes at most 64 MiB");
    std::string out = "# ladarvr scene from-cloud: the triangles of " + core::printable(mesh.filename().string(), 200) +
                      ", z up\no target\n";
    char buffer[160];
    for (const glm::dvec3& v : m.vertices) {
        std::snprintf(buffer, sizeof buffer, "v %.9g %.9g %.9g\n", v.x, v.y, v.z);
        out += buffer;
    }
    for (const glm::uvec3& t : m.triangles) {
        std::snprintf(buffer, sizeof buffer, "f %u %u %u\n", t.x + 1, t.y + 1, t.z + 1);
        out += buffer;
    }
    return out;
}

bool vehicleAsObj(const VehiclePlacement& v) { return v.up_y || v.mesh.extension() == ".gltf"; }

std::string vehicleFileName(const VehiclePlacement& v) {
    return vehicleAsObj(v) ? "target.obj" : "target" + v.mesh.extension().string();
}

std::string terrainObj(const TerrainMesh& t) {
    std::string out = "# ladarvr scene from-cloud: the survey's ground, a regular grid of " + std::to_string(t.nx) +
                      " x " + std::to_string(t.ny) + " nodes every " + fixed(t.cell_m, 3) + " m\no ground\n";
    out.reserve(out.size() + std::size_t(t.nx) * std::size_t(t.ny) * 64);
    for (int j = 0; j < t.ny; ++j)
        for (int i = 0; i < t.nx; ++i) vertexLine(out, t.x0_m + i * t.cell_m, t.y0_m + j * t.cell_m, t.at(i, j));
    char buffer[160];
    for (int j = 0; j + 1 < t.ny; ++j)
        for (int i = 0; i + 1 < t.nx; ++i) {
            const long a = long(j) * t.nx + i + 1, b = a + 1, c = a + t.nx + 1, d = a + t.nx;  // 1-based
            std::snprintf(buffer, sizeof buffer, "f %ld %ld %ld\nf %ld %ld %ld\n", a, b, c, a, c, d);
            out += buffer;
        }
    return out;
}

std::string boxesObj(const std::vector<std::array<std::int32_t, 3>>& boxes, double voxel_m) {
    std::string out = "# ladarvr scene from-cloud: the survey's other points, one box of " + fixed(voxel_m, 3) +
                      " m per occupied voxel (faces between two boxes left out)\no environment\n";
    std::string faces;
    long next = 1;
    char buffer[160];
    for (const auto& k : boxes)
        for (int axis = 0; axis < 3; ++axis)
            for (int side = 0; side < 2; ++side) {
                std::array<std::int32_t, 3> n = k;
                n[axis] += side ? 1 : -1;
                if (std::binary_search(boxes.begin(), boxes.end(), n)) continue;
                // The face's corners counter-clockwise seen from outside: (u, v) with
                // (axis, u, v) cyclic, reversed on the low side.
                const int u = (axis + 1) % 3, v = (axis + 2) % 3;
                const int order[2][4][2] = {{{0, 0}, {0, 1}, {1, 1}, {1, 0}}, {{0, 0}, {1, 0}, {1, 1}, {0, 1}}};
                for (const auto& corner : order[side]) {
                    double p[3];
                    p[axis] = (k[axis] + side) * voxel_m;
                    p[u] = (k[u] + corner[0]) * voxel_m;
                    p[v] = (k[v] + corner[1]) * voxel_m;
                    vertexLine(out, p[0], p[1], p[2]);
                }
                std::snprintf(buffer, sizeof buffer, "f %ld %ld %ld\nf %ld %ld %ld\n", next, next + 1, next + 2, next,
                              next + 2, next + 3);
                faces += buffer;
                next += 4;
            }
    return out + faces;
}

std::string sceneJson(const SceneFromCloud& s) {
    std::string j = "{\n  \"comment\": " +
                    quoted("made by ladarvr scene from-cloud from " + s.survey.filename().string() +
                           "; local frame = the survey's coordinates in metres minus " + triple(s.offset_m, 3)) +
                    ",\n  \"meshes\": [\n    {\"file\": \"ground.obj\", \"role\": \"ground\"}";
    if (!s.boxes.empty()) j += ",\n    {\"file\": \"environment.obj\", \"role\": \"environment\"}";
    if (s.vehicle) {
        const PlacedVehicle& v = *s.vehicle;
        j += ",\n    {\"file\": " + quoted(v.file) + ", \"role\": \"target\", \"position\": " + triple(v.position, 6) +
             ", \"yaw_deg\": " + fixed(v.yaw_deg, 6) + ", \"pitch_deg\": " + fixed(v.pitch_deg, 6) +
             ", \"roll_deg\": " + fixed(v.roll_deg, 6) + "}";
    }
    return j + "\n  ]\n}\n";
}

std::string recordJson(const SceneFromCloud& s, const SceneFromCloudOptions& o) {
    const TerrainMesh& t = s.terrain;
    std::string j =
        "{\n  \"survey\": " + quoted(std::filesystem::absolute(s.survey).string()) +
        ",\n  \"units\": " + quoted(describe(s.units)) + ",\n  \"offset_m\": " + triple(s.offset_m, 3) +
        ",\n  \"points\": " + std::to_string(s.points) + ",\n  \"ground_points\": " + std::to_string(s.ground_points) +
        ",\n  \"dropped_high\": " + std::to_string(s.dropped_high) +
        ",\n  \"dropped_low\": " + std::to_string(s.dropped_low) + ",\n  \"ground_from\": " + quoted(s.ground_from) +
        ",\n  \"terrain\": {\"cell_m\": " + fixed(t.cell_m, 3) + ", \"nx\": " + std::to_string(t.nx) +
        ", \"ny\": " + std::to_string(t.ny) + ", \"observed_nodes\": " + std::to_string(t.observed_nodes) +
        "},\n  \"voxel_m\": " + fixed(s.voxel_m, 4) + ",\n  \"voxel_requested_m\": " + fixed(s.voxel_requested_m, 4) +
        ",\n  \"boxes\": " + std::to_string(s.boxes.size()) + ",\n  \"max_boxes\": " + std::to_string(o.max_boxes) +
        ",\n  \"vehicle\": ";
    if (!s.vehicle) return j + "null\n}\n";
    const PlacedVehicle& v = *s.vehicle;
    return j + "{\"mesh\": " + quoted(std::filesystem::absolute(o.vehicle.mesh).string()) +
           (o.vehicle.up_y ? ", \"up\": \"y\"" : "") + ", \"file\": " + quoted(v.file) +
           ", \"size_m\": " + triple(v.size_m, 3) + ", \"bottom_centre\": " + triple(v.footprint_centre, 3) +
           ", \"bottom_centre_world\": " + triple(v.footprint_centre + s.offset_m, 3) +
           ", \"yaw_deg\": " + fixed(v.yaw_deg, 3) + ", \"slope\": " + fixed(v.slope, 4) +
           ", \"roughness_m\": " + fixed(v.roughness_m, 3) + ", \"seed\": " + std::to_string(o.vehicle.seed) +
           ", \"attempts\": " + std::to_string(v.attempts) + "}\n}\n";
}

bool isSceneFromCloudFile(const std::string& name) {
    return name == "scene.json" || name == "ground.obj" || name == "environment.obj" || name == "from_cloud.json" ||
           name == "target" || name.starts_with("target.");
}

void writeSceneFolder(const std::filesystem::path& dir, const SceneFromCloud& s, const SceneFromCloudOptions& o) {
    std::string vehicle_bytes;
    if (s.vehicle && !vehicleAsObj(o.vehicle))
        vehicle_bytes = platform::readTextFile(o.vehicle.mesh, kMaxVehicleBytes,
                                               "scene from-cloud: --vehicle '" + o.vehicle.mesh.string() + "'");
    platform::removeStaleTemporaries(dir.parent_path().empty() ? "." : dir.parent_path(), isSceneFromCloudFile);
    platform::AtomicFolder folder(dir, isSceneFromCloudFile);
    folder.writeFile("ground.obj", terrainObj(s.terrain));
    if (!s.boxes.empty()) folder.writeFile("environment.obj", boxesObj(s.boxes, s.voxel_m));
    if (s.vehicle) folder.writeFile(s.vehicle->file, vehicleAsObj(o.vehicle) ? s.vehicle->obj_text : vehicle_bytes);
    folder.writeFile("scene.json", sceneJson(s));
    folder.writeFile("from_cloud.json", recordJson(s, o));
    folder.commit();
}

}  // namespace sim
