// study/plan.hpp: a target-search study's plan (PLAN.json), read strictly.
//
//   {"trials": [{"cloud": "a.pcd" | "scene": "s.json", "candidates": "c.json",
//                "time_limit_s": 120, "name": "optional label"}, ...],
//    "shuffle_seed": 1,                                   (optional: trial order shuffled)
//    "hit_radius_m": 1.0,                                 (optional)
//    "orbit": {"radius_m": 60, "height_m": 40, "period_s": 60},   (optional, automatic mode)
//    "generate": {"xres": 128, "yres": 128, "views": 100,        (optional, scene trials)
//                 "ground": "ransac"}}
// Paths are relative to the plan's folder. docs/study.md explains each field.
#pragma once
#include <core/candidates.hpp>
#include <viewer/viewer.hpp>

#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace study {

/// A trial's name is a label for the screen and stderr: at most this many characters shown.
inline constexpr std::size_t kMaxTrialNameChars = 120;

struct PlanTrial {
    std::filesystem::path cloud;       // a cloud file, or
    std::filesystem::path scene;       // a scene whose cloud is generated at the trial
    std::filesystem::path candidates;  // optional
    double time_limit_s = 120.0;       // 0: none
    std::string name;                  // shown on the ready screen and in progress lines; default: the
                                       // file name; printable (platform::printableUtf8, kMaxTrialNameChars)
    std::string source;                // the cloud or scene as written in the plan (trials.csv)
    // A design's condition (study/design.hpp) sets these; a plan leaves them unset.
    std::optional<viewer::ColourMode> colour;    // point colours for this trial
    std::optional<bool> eye_dome;                // eye-dome lighting on or off
    std::optional<viewer::ViewMode> start_mode;  // the mode the trial starts in
    std::string detector;           // "baseline" or a model file: candidates detected in the cloud; empty: `candidates`
    std::optional<unsigned> tools;  // viewer::TrialTool bits offered; unset: every tool
    std::optional<bool> cut;        // the cutting volume on (or off) at the start
    std::optional<double> cut_radius_m;  // its radius
    double min_ready_s = 0.0;            // the ready screen stays up at least this long (a break)
};

struct Plan {
    std::vector<PlanTrial> trials;
    std::optional<std::uint64_t> shuffle_seed;
    double hit_radius_m = 1.0;
    double orbit_radius_m = 60.0, orbit_height_m = 40.0, orbit_period_s = 60.0;
    int xres = 128, yres = 128, views = 100;  // generated clouds (the generator's defaults)
    /// The generated clouds' ground filter, one of kPlanGrounds: the generator's --ground
    /// (ransac, the paper's; smrf; csf), or white (its --white: no ground filter, no colours).
    std::string ground = "ransac";
};

/// The names a plan's generate.ground takes.
inline constexpr std::array<std::string_view, 4> kPlanGrounds = {"ransac", "smrf", "csf", "white"};

/// The largest plan read.
inline constexpr std::size_t kMaxPlanBytes = std::size_t(1) << 20;

/// Parses plan text; relative paths are taken from `base`. Throws core::Error("study:
/// <name>: trials[2].time_limit_s -1 is not in [0, 86400]") naming the field and what is
/// allowed; unknown keys are refused (a misspelt key would silently change a study).
Plan parsePlan(std::string_view text, const std::string& name, const std::filesystem::path& base);
/// Reads a plan file (regular file, at most kMaxPlanBytes) and checks that every cloud,
/// scene and candidates file it names is a readable regular file.
Plan readPlan(const std::filesystem::path& file);

/// The order the trials run in: 0..n-1, or shuffled with the plan's seed (core::shuffle,
/// the same order on every platform).
std::vector<int> trialOrder(const Plan& plan);

}  // namespace study
