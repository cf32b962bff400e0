// core/scene.hpp: a scene in memory: triangle meshes with roles, in a local frame.
// Scene files and their loading: io/scene_file.hpp.
#pragma once
#include <core/frames.hpp>
#include <core/roles.hpp>

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace core {

/// A mesh entry's 'reflectance' when the scene file gives none.
inline constexpr double kDefaultReflectance = 0.5;

/// One triangle mesh in the scene's local frame (world - origin).
struct Mesh {
    std::string name;  // the file name as written in the scene
    Role role = Role::Environment;
    glm::dvec3 position{0.0};                  // the entry's 'position', world metres
    std::vector<glm::vec3> vertices;           // local frame, metres
    std::vector<glm::uvec3> triangles;         // indices into vertices
    double reflectance = kDefaultReflectance;  // Lambertian reflectance at the Ladar's wavelength, [0, 1]
    int asprs_class = -1;                      // 'class' (0..255) for LAS output, -1: by role
};

/// One mesh entry of a scene file, as written (before its mesh file is read): what a
/// tool that writes scene files (the corpus) copies and changes.
struct SceneEntry {
    std::string file;  // as written, relative to the scene file
    Role role = Role::Environment;
    glm::dvec3 position{0.0};  // world metres
    double yaw_deg = 0.0;
    double pitch_deg = 0.0;  // about the mesh's own y axis, before the yaw
    double roll_deg = 0.0;   // about the mesh's own x axis, before the pitch
    double scale = 1.0;
    bool up_y = false;  // "up": "y"
    double reflectance = kDefaultReflectance;
    int asprs_class = -1;  // 'class', -1: not given (by role)
};

/// A mesh entry's tilt of `v` (its own frame, scaled, up axis applied), before its yaw:
/// Ry(pitch) * Rx(roll) * v. A rotation of zero degrees is skipped, not multiplied by one,
/// so an entry without a tilt places its vertices exactly as the yaw alone does.
glm::dvec3 tilt(const glm::dvec3& v, double pitch_deg, double roll_deg);

struct Scene {
    std::filesystem::path source;              // the scene file, for messages
    glm::dvec3 origin{0.0};                    // world coordinates of the local frame's origin
    std::optional<glm::dvec3> written_origin;  // the file's "origin", when it has one
    std::vector<SceneEntry> entries;           // every entry of the file, in order (any role)
    std::vector<Mesh> meshes;
    std::size_t skipped_triangles = 0;  // zero-area triangles dropped at load
    /// Triangles with a NaN/inf vertex dropped at load (only with skip_nonfinite).
    std::size_t skipped_nonfinite_triangles = 0;

    /// Bounds (local frame) of the meshes whose role is in `roles`; empty if none.
    Bounds bounds(RoleMask roles = RoleMask::all()) const;
    std::size_t triangleCount() const;
    bool hasRole(Role r) const;
};

}  // namespace core
