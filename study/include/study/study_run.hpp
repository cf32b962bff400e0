// study/study_run.hpp: a study as `ladarvr study` runs it (docs/study.md): the plan read
// and the command's overrides applied, study.json, the visibility metric of each scene,
// the trials in the viewer with their files written as they end; and the replay of one
// trial's trace in the mirror. app/ parses the command line into these options and makes
// the output paths' folders; everything else about a study happens here.
#pragma once
#include <study/design.hpp>
#include <study/plan.hpp>
#include <study/resume.hpp>
#include <study/study_source.hpp>
#include <viewer/viewer.hpp>

#include <chrono>
#include <filesystem>
#include <optional>

namespace study {

struct StudyOptions {
    std::filesystem::path plan;    // PLAN.json
    std::filesystem::path design;  // DESIGN.json instead of a plan (study/design.hpp)
    std::string participant;       // with a design: whose session runs
    std::filesystem::path out;     // the study's folder (study/study_folder.hpp)
    std::filesystem::path script;  // operator actions (viewer::readScript); empty: none
    /// The window, mirror, colours, frames, timeout, run log, XR use and pointer; the
    /// automatic orbit is set from the plan and the overrides below.
    viewer::ViewerOptions viewer;
    /// Overrides of the plan's values; empty: the plan's.
    std::optional<double> hit_radius_m, orbit_radius_m, orbit_height_m, orbit_period_s;
    bool metric = true;  // false: visibility_metric left empty
    /// The ground under a cloud trial's file for above-ground colours (StudySource::
    /// setTerrain); empty: such a trial shows height colours, said on its panel.
    TerrainStarter terrain;
};

class StudyRun {
  public:
    /// Reads the plan and the script, applies the overrides and validates the viewer's
    /// options, so bad input fails before anything is written. Throws core::Error naming
    /// the file or value (e.g. "study: --hit-radius must be > 0 m").
    explicit StudyRun(StudyOptions options);

    /// The viewer's options the trials run with (the orbit from the plan).
    const viewer::ViewerOptions& viewerOptions() const { return options_.viewer; }
    /// The plan as read (trials in the plan's order); for a design, the participant's
    /// session (trials in run order).
    const Plan& plan() const { return plan_; }

    /// Checks options.out (made by the caller): a plan needs it new or empty
    /// (checkStudyFolder); a design's session may also resume there (findResumePoint).
    void checkFolder();

    /// Runs the study into options.out, which the caller has made and checked with
    /// checkStudyFolder: writes study.json, computes the scenes' metric, then runs the
    /// trials. The viewer's timeout counts from `started` (when the command started).
    /// Returns the viewer's exit status, 1 when a file could not be written (said on
    /// stderr); prints "ladarvr: study: N of M trials written to DIR/trials.csv".
    int run(std::chrono::steady_clock::time_point started);

  private:
    StudyOptions options_;
    Plan plan_;
    std::optional<Design> design_;       // a design's session: its design,
    Session session_;                    // the participant's trials,
    std::string design_sha256_;          // the design file's SHA-256,
    std::optional<ResumePoint> resume_;  // and what a stopped run already wrote
};

/// Replays trial `trial_number` (1.. in run order) of the study in `dir`: its cloud
/// found through dir/study.json, then its trace's head poses, zoom, mode and pointer hit
/// in the desktop mirror.
class Replay {
  public:
    /// Reads dir/study.json, the plan and trace_<trial_number>.csv (a trace with the study
    /// columns, io/trace_file.hpp) and validates `viewer` (use_xr is turned off).
    /// Throws core::Error naming the file, or "study: --trial N: allowed 1..M".
    Replay(const std::filesystem::path& dir, int trial_number, viewer::ViewerOptions viewer);

    const viewer::ViewerOptions& viewerOptions() const { return options_; }
    /// A cloud trial replayed in above-ground colours gets its terrain from `start`, as the
    /// study's trial did (StudyOptions::terrain).
    void setTerrain(TerrainStarter start) { start_terrain_ = std::move(start); }

    /// Shows the replay; returns the viewer's exit status.
    int run();

  private:
    Plan plan_;
    std::vector<int> order_;
    int trial_ = 0;  // 0-based run position
    viewer::ViewerOptions options_;
    TerrainStarter start_terrain_;
};

}  // namespace study
