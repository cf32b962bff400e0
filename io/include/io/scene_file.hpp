// io/scene_file.hpp: scene files: a list of meshes with roles (core/scene.hpp), in JSON.
//
// Scene file (JSON):
//   {
//     "origin": [x, y, z],          // optional, world metres (double); the local frame's
//                                   // origin. Default: the first mesh's position.
//     "meshes": [
//       { "file": "house.obj",      // any format Assimp reads, relative to the scene file
//         "role": "environment",    // ground | environment | target
//         "position": [x, y, z],    // world metres, default [0,0,0]
//         "yaw_deg": 0,             // rotation about world z, default 0
//         "pitch_deg": 0,           // tilt about the mesh's own y axis, [-90, 90], default 0
//         "roll_deg": 0,            // tilt about the mesh's own x axis, [-90, 90], default 0
//         "scale": 1,               // > 0, default 1
//         "up": "z",                // the mesh file's own up axis: y | z, default z
//         "class": 6 }              // ASPRS class in LAS output (0..255), default by role
//     ]
//   }
// World vertex = position + Rz(yaw) * Ry(pitch) * Rx(roll) * scale * (up == y ? (x, -z, y) : (x, y, z)).
// Unknown keys are errors (they are usually typos).
#pragma once
#include <core/scene.hpp>

#include <cstddef>
#include <filesystem>
#include <string_view>

namespace io {

struct SceneLoadOptions {
    /// Meshes whose role is not in this set are not loaded at all (--roles).
    core::RoleMask roles = core::RoleMask::all();
    /// Require at least one target mesh in the file (the generator's default).
    bool require_target = true;
    /// Drop triangles that use a NaN/inf vertex (counted in skipped_nonfinite_triangles)
    /// instead of rejecting the scene. Off: such a mesh is an Error naming the vertex.
    bool skip_nonfinite = false;
};

/// The largest scene file read: scenes list meshes, they are kilobytes; this refuses a
/// runaway file (or /dev/zero behind a link) before it fills the memory.
inline constexpr std::size_t kMaxSceneBytes = std::size_t(16) << 20;

/// Loads and validates a scene file. Throws Error("scene: <file>: ...") naming the file
/// (scene or mesh) and the reason for: unreadable JSON, unknown key, wrong type, missing
/// or unreadable mesh, NaN vertices, unknown role, no target, non-finite transform,
/// non-positive scale, no mesh left by options.roles, a duplicate key or a NUL character
/// in the JSON, a scene file that is not a regular file or is over kMaxSceneBytes. Zero-area triangles are dropped and
/// counted in skipped_triangles.
core::Scene loadScene(const std::filesystem::path& file, const SceneLoadOptions& options = {});

/// As loadScene, from JSON text already in memory; `file` names it in messages and mesh
/// paths are relative to its directory (for fuzzing and for callers that build JSON).
core::Scene loadSceneJson(std::string_view json_text, const std::filesystem::path& file,
                          const SceneLoadOptions& options = {});

/// The vertices of one mesh file in its own frame, `scale` and the up axis applied (no
/// yaw, no position), with the checks loadScene makes of a mesh file; `where` names it
/// in messages, e.g. Error("<where>: mesh file 'a.obj' is a FIFO (named pipe); ...").
std::vector<glm::dvec3> loadMeshVertices(const std::filesystem::path& file, bool up_y, double scale,
                                         const std::string& where);

/// The same vertices with the triangles (indices into them) of every mesh of the file, as
/// loadScene reads them: what a copy of the mesh in another format must hold.
struct MeshTriangles {
    std::vector<glm::dvec3> vertices;
    std::vector<glm::uvec3> triangles;
};
MeshTriangles loadMeshTriangles(const std::filesystem::path& file, bool up_y, double scale, const std::string& where);

/// The files loadScene read for `scene` when it loaded the meshes of the roles `roles`
/// (SceneLoadOptions::roles): the scene file, then the mesh file of each such entry, in
/// the entries' order (a file used twice is named twice). A command adds them to its
/// platform::InputSet so that no output of the run replaces one.
std::vector<std::filesystem::path> sceneFiles(const core::Scene& scene, core::RoleMask roles);

/// The bundled demo scene: assets/demo/scene.json of the source tree this binary was built
/// from (nothing installs the assets elsewhere). Whether it exists is loadScene's to check.
std::filesystem::path demoScenePath();

}  // namespace io
