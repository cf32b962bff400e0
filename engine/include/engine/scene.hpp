// engine/scene.hpp: a scene is a list of meshes with roles, loaded from a JSON file.
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
//         "scale": 1,               // > 0, default 1
//         "up": "z",                // the mesh file's own up axis: y | z, default z
//         "class": 6 }              // ASPRS class in LAS output (0..255), default by role
//     ]
//   }
// World vertex = position + Rz(yaw) * scale * (up == y ? (x, -z, y) : (x, y, z)).
// Unknown keys are errors (they are usually typos).
#pragma once
#include <engine/frames.hpp>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace engine {

enum class Role : std::uint8_t { Ground = 0, Environment = 1, Target = 2 };
inline constexpr int kRoleCount = 3;

/// "ground", "environment" or "target".
std::string_view roleName(Role r);
/// Parses a role name; throws Error("<context>: role 'x' is not one of ground, environment, target").
Role parseRole(std::string_view name, std::string_view context);

/// A set of roles as a bit mask (bit i = Role i).
struct RoleMask {
    std::uint8_t bits = 0b111;
    bool has(Role r) const { return (bits >> static_cast<int>(r)) & 1u; }
    static RoleMask all() { return {}; }
    static RoleMask of(std::initializer_list<Role> roles);
    /// Parses "target,environment"; throws Error naming `parameter` on an unknown or empty list.
    static RoleMask parse(std::string_view list, std::string_view parameter);
};

/// A mesh entry's 'reflectance' when the scene file gives none.
inline constexpr double kDefaultReflectance = 0.5;

/// One triangle mesh in the scene's local frame (world - origin).
struct Mesh {
    std::string name;                        // the file name as written in the scene
    Role role = Role::Environment;
    glm::dvec3 position{0.0};                // the entry's 'position', world metres
    std::vector<glm::vec3> vertices;         // local frame, metres
    std::vector<glm::uvec3> triangles;       // indices into vertices
    double reflectance = 0.5;                // Lambertian reflectance at the Ladar's wavelength, [0, 1]
    int asprs_class = -1;                    // 'class' (0..255) for LAS output, -1: by role
};

/// One mesh entry of a scene file, as written (before its mesh file is read): what a
/// tool that writes scene files (the corpus) copies and changes.
struct SceneEntry {
    std::string file;                        // as written, relative to the scene file
    Role role = Role::Environment;
    glm::dvec3 position{0.0};                // world metres
    double yaw_deg = 0.0;
    double scale = 1.0;
    bool up_y = false;                       // "up": "y"
    double reflectance = kDefaultReflectance;
    int asprs_class = -1;                    // 'class', -1: not given (by role)
};

struct Scene {
    std::filesystem::path source;            // the scene file, for messages
    glm::dvec3 origin{0.0};                  // world coordinates of the local frame's origin
    std::optional<glm::dvec3> written_origin;  // the file's "origin", when it has one
    std::vector<SceneEntry> entries;         // every entry of the file, in order (any role)
    std::vector<Mesh> meshes;
    std::size_t skipped_triangles = 0;       // zero-area triangles dropped at load
    /// Triangles with a NaN/inf vertex dropped at load (only with skip_nonfinite).
    std::size_t skipped_nonfinite_triangles = 0;

    /// Bounds (local frame) of the meshes whose role is in `roles`; empty if none.
    Bounds bounds(RoleMask roles = RoleMask::all()) const;
    std::size_t triangleCount() const;
    bool hasRole(Role r) const;
};

struct SceneLoadOptions {
    /// Meshes whose role is not in this set are not loaded at all (--roles).
    RoleMask roles = RoleMask::all();
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
Scene loadScene(const std::filesystem::path& file, const SceneLoadOptions& options = {});

/// As loadScene, from JSON text already in memory; `file` names it in messages and mesh
/// paths are relative to its directory (for fuzzing and for callers that build JSON).
Scene loadSceneJson(std::string_view json_text, const std::filesystem::path& file,
                    const SceneLoadOptions& options = {});

/// The vertices of one mesh file in its own frame, `scale` and the up axis applied (no
/// yaw, no position), with the checks loadScene makes of a mesh file; `where` names it
/// in messages, e.g. Error("<where>: mesh file 'a.obj' is a FIFO (named pipe); ...").
std::vector<glm::dvec3> loadMeshVertices(const std::filesystem::path& file, bool up_y, double scale,
                                         const std::string& where);
/// The bundled demo scene (assets/demo/scene.json in the source tree, or installed copy).
std::filesystem::path demoScenePath();

}  // namespace engine
