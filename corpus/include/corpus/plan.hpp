// corpus/plan.hpp: from a SPEC and an item index to a concrete scene and generator options.
//
// The planner loads the base scene once (meshes, the ground's ray caster, the environment
// meshes' boxes, the target models) and then plans any item on its own, from
// (seed, index) alone: the sampled values, the target's model, yaw and place, the
// environment meshes kept, the orbit centre C and sim::GenerateOptions. plan() is const
// and thread-safe.
#pragma once
#include <corpus/spec.hpp>

#include <core/frames.hpp>
#include <core/scene.hpp>
#include <sim/generator.hpp>

#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace corpus {

/// One mesh entry of a concrete scene file (core/scene.hpp's fields).
struct MeshEntry {
    std::filesystem::path file;  // absolute
    std::string written;         // as the base scene or the SPEC wrote it
    std::string role;
    glm::dvec3 position{0.0};
    double yaw_deg = 0.0;
    double pitch_deg = 0.0, roll_deg = 0.0;  // written when not zero
    double scale = 1.0;
    std::string up = "z";
    double reflectance = core::kDefaultReflectance;
    int asprs_class = -1;  // 'class'; -1: not given (by role)
};

struct ItemPlan {
    std::size_t index = 0;
    std::string id;  // zero-padded index: the item's folder name
    std::uint64_t item_seed = 0;
    std::map<std::string, double> values;  // every varied numeric key, as drawn
    std::string target_file;               // the target model as written (SPEC or scene)
    double target_yaw_deg = 0.0;
    glm::dvec3 target_position_world{0.0};
    core::Bounds target_box_world;  // the placed target's box (world metres)
    int placement_draws = 0;        // draws of the target's place (1 = first fit)
    int centre_draws = 0;
    std::size_t environment_kept = 0, environment_total = 0;
    std::optional<glm::dvec3> centre_world;  // C when centre_offset_m varies
    sim::GenerateOptions options;            // threads and progress are the caller's
    std::optional<glm::dvec3> origin;        // the base scene's "origin" if it has one
    std::vector<MeshEntry> meshes;

    /// The concrete scene file: mesh paths relative to `folder` (absolute when `folder`
    /// is empty or shares no folder with the mesh but the root), a comment holding the generate options that replay the cloud.
    std::string sceneText(const std::filesystem::path& folder) const;
    /// The `ladarvr generate` options (besides --scene and --out) that make this cloud.
    std::vector<std::string> generateArgs() const;
};

/// Most draws of a place before an item is an error.
inline constexpr int kMaxPlacementDraws = 200;

/// The folder name of item `index` of a corpus of `count` items: the index zero-padded
/// to at least 4 digits, enough for count - 1.
std::string itemId(std::size_t index, std::size_t count);

class Planner {
  public:
    /// Loads the base scene and the target models. Throws core::Error naming the SPEC
    /// key (e.g. target variations on a scene without exactly one target mesh).
    explicit Planner(const Spec& spec);
    ~Planner();
    Planner(const Planner&) = delete;
    Planner& operator=(const Planner&) = delete;

    /// Item `index` (< spec.count). Throws core::Error("corpus: item <id>: ...") when
    /// its target or C cannot be placed (every draw met another mesh's box or left the ground).
    ItemPlan plan(std::size_t index) const;
    /// The folder name of item `index`: itemId(index, spec().count).
    std::string itemId(std::size_t index) const;
    /// World boxes of the environment meshes of the base scene, in scene order.
    const std::vector<core::Bounds>& environmentBoxes() const;
    /// The ground's height (world z) under world (x, y) by a vertical ray; empty on a miss.
    std::optional<double> groundZ(double x_world, double y_world) const;
    const Spec& spec() const;

    struct State;

  private:
    std::unique_ptr<State> state_;
};

}  // namespace corpus
