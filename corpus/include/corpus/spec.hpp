// corpus/spec.hpp: SPEC.json, the description of a family of scenes and sensor settings.
//
//   { "scene": "base.json", "count": 1000, "seed": 7,
//     "vary": { "altitude_m": {"min": 200, "max": 400},   // uniform
//               "resolution": [128, 256],                 // one of a list
//               "views": 50,                              // fixed
//               "target_files": ["tank.obj", {"file": "truck.glb", "up": "y"}] },
//     "metric": true,                 // or {"views": 20, "width": 256, "height": 256}
//     "format": "pcd" }               // cloud format: pcd, pcd-ascii, ply, ply-ascii
//
// Paths are relative to the SPEC file. Every key is checked before any work; a bad one
// is an core::Error("corpus: <spec>: <key>: ...; allowed ...") naming it. The list of
// vary keys and what each may hold is kVaryKeys (docs/corpus.md shows it as a table).
#pragma once
#include <io/cloud_io.hpp>

#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace sim {
struct GenerateOptions;
}

namespace corpus {

/// How one numeric parameter varies over the items.
struct NumberVary {
    enum class Kind { Fixed, Uniform, Choice };
    Kind kind = Kind::Fixed;
    double min = 0.0, max = 0.0;  // Uniform: [min, max]; Fixed: min == max == the value
    std::vector<double> choices;  // Choice: drawn with equal probability
    bool integer = false;         // integer parameter: uniform over min..max inclusive
    double lowest() const;        // the smallest value it can take
    double highest() const;       // the largest
};

/// A target model: a mesh file with the scene-file fields that say how to read it.
struct TargetModel {
    std::filesystem::path file;  // absolute
    std::string written;         // as written in the SPEC (for the manifest)
    std::string up = "z";        // the file's up axis: y | z
    double scale = 1.0;
};

/// The metric's settings per item ("metric": true takes metric::MetricOptions' defaults).
struct MetricSpec {
    bool enabled = false;
    int views = 100;
    int width = 512;
    int height = 512;
};

/// One vary key: its name, whether it is an integer, the range a value must lie in, what
/// it changes (for the docs and the messages), and, for a generator parameter, the
/// `generate` options that take its value and how it sets sim::GenerateOptions.
struct VaryKey {
    std::string_view name;
    bool integer;
    double lowest, highest;  // allowed values (closed), before sim's own checks
    std::string_view what;
    /// The `generate` options (space-separated) that each take the value in an item's
    /// replay line; empty for the keys the planner applies itself (placements, kept
    /// environment).
    std::string_view options = {};
    /// Sets the generator parameter to a value (integers already whole); null where
    /// `options` is empty.
    void (*apply)(sim::GenerateOptions& o, double value) = nullptr;
    /// For a key that picks one of named things (sensor_preset): the names, value i
    /// standing for names()[i]; the SPEC may give the names, the replay line writes them.
    std::span<const std::string_view> (*names)() = nullptr;
};

/// Every key `vary` accepts, besides target_files: the one table of vary keys.
extern const std::vector<VaryKey> kVaryKeys;
/// The entry of kVaryKeys named `name`; null when there is none.
const VaryKey* findVaryKey(std::string_view name);
/// Sets the generator parameter named by vary key `key` to `value`; keys that are not
/// generator parameters (the target's and C's placement, environment_keep_fraction) are
/// left to the planner and ignored here.
void applyToOptions(sim::GenerateOptions& o, std::string_view key, double value);

struct Spec {
    std::filesystem::path file;   // the SPEC file, absolute
    std::filesystem::path scene;  // the base scene, absolute
    std::string sha256;           // of the SPEC file's bytes: outputs remember their SPEC
    std::size_t count = 0;
    std::uint64_t seed = 0;
    std::map<std::string, NumberVary> numbers;  // vary keys given (not target_files)
    std::vector<TargetModel> target_files;      // empty: the base scene's target
    MetricSpec metric;
    io::CloudFormat format = io::CloudFormat::PcdBinary;
    /// "placement": "triangles": a moved target is blocked by the triangles of an environment
    /// mesh (their boxes), not by the mesh's whole box; for a mesh that covers the whole
    /// scene, such as the boxes `scene from-cloud` makes of a real survey. Default "boxes".
    bool place_by_triangles = false;

    bool varies(std::string_view key) const;
    /// The cloud's file name in an item folder: cloud.pcd or cloud.ply.
    std::string cloudName() const;
};

/// The largest SPEC file read, and the most items one SPEC may describe.
inline constexpr std::size_t kMaxSpecBytes = std::size_t(1) << 20;
inline constexpr std::size_t kMaxItems = 100'000'000;

/// Reads and checks a SPEC file (see above). Throws core::Error naming the key.
Spec loadSpec(const std::filesystem::path& file);
/// As loadSpec, from text already read; `file` locates relative paths and names messages.
Spec parseSpec(std::string_view text, const std::filesystem::path& file);

}  // namespace corpus
