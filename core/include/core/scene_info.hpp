// core/scene_info.hpp: what a loaded scene holds, measured: each mesh's size and
// position, the target's size and its height above the ground beneath it, and the
// warnings those measures call for (a target modelled in millimetres, or floating far
// above the ground). `ladarvr scene info` prints them; `ladarvr generate` warns with them.
#pragma once
#include <core/scene.hpp>

#include <optional>
#include <string>
#include <vector>

namespace core {

struct MeshSummary {
    std::string file;  // as written in the scene
    Role role = Role::Environment;
    std::size_t triangles = 0;
    glm::dvec3 position{0.0};  // the entry's 'position', world metres
    Bounds bounds;             // of the vertices its triangles use, local frame
};

struct TargetSummary {
    Bounds bounds;  // of every target mesh, local frame
    /// Local z of the highest ground triangle crossed by the vertical line through the
    /// centre of `bounds`; empty when no ground triangle lies above or below that point.
    std::optional<double> ground_z;
    /// bounds.lo.z - ground_z: > 0 floats above the ground, < 0 sinks into it.
    std::optional<double> height_above_ground_m;
};

struct SceneSummary {
    glm::dvec3 origin{0.0};
    std::vector<MeshSummary> meshes;
    Bounds bounds;  // of every mesh, local frame
    std::size_t triangles = 0;
    bool has_ground = false;
    std::optional<TargetSummary> target;  // empty when no mesh has role target
};

/// Measures `scene` (every mesh it holds, whatever its role).
SceneSummary summarize(const Scene& scene);

/// Local z of the highest triangle of a ground-role mesh that the vertical line through
/// (x, y) (local frame) crosses; empty when there is none. A triangle standing vertical
/// (zero area seen from above) is never crossed.
std::optional<double> groundHeightAt(const Scene& scene, double x, double y);

/// A target wider, deeper or taller than this is taken for a unit mistake (a mesh in
/// millimetres or centimetres read as metres).
inline constexpr double kMaxTargetSize_m = 30.0;
/// A target whose bottom is farther than this above or below the ground under its
/// centre is taken for a misplaced one.
inline constexpr double kMaxTargetGroundGap_m = 1.0;

/// One line each (no prefix) for what looks wrong with the target: larger than
/// kMaxTargetSize_m, floating above or sunk below the ground by more than
/// kMaxTargetGroundGap_m, or no ground under it although the scene has ground meshes.
std::vector<std::string> targetWarnings(const SceneSummary& summary);

}  // namespace core
