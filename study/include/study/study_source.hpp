// study/study_source.hpp: a plan's trials for the viewer (viewer::TrialSource): each
// trial's cloud file is opened through viewer::openPointSource and streamed whole into
// the viewer's feed for that trial (a COPC file too: hits are judged against every target
// point), or its scene's cloud is generated on a worker thread into that feed. A cloud
// trial in above-ground colours gets the ground under its file from a terrain starter
// (`ladarvr study` hands it view's, app/src/view_terrain.hpp), built while its ready
// screen is up and stopped when the trial ends.
#pragma once
#include <study/plan.hpp>
#include <viewer/terrain_feed.hpp>
#include <viewer/trial.hpp>
#include <viewer/viewer.hpp>

#include <core/candidates.hpp>
#include <core/scene.hpp>

#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <thread>
#include <vector>

namespace sim {
struct GenerateOptions;  // sim/generator.hpp
}

namespace study {

/// The ground under a cloud file being built on a thread of its own; destroying it stops
/// that thread and joins it.
class TerrainJob {
  public:
    virtual ~TerrainJob() = default;
};

/// A cloud file's terrain as it starts: the feed it is published to (null: the cloud needs
/// none, its points carry their heights above ground) and the job building it (null:
/// nothing runs, its failure is in the feed already).
struct CloudTerrain {
    std::shared_ptr<viewer::TerrainFeed> feed;
    std::unique_ptr<TerrainJob> job;
};

/// Starts the terrain of cloud file `cloud` for above-ground colours. Throws nothing: a
/// terrain that cannot be built is the feed's failure.
using TerrainStarter = std::function<CloudTerrain(const std::filesystem::path& cloud)>;

/// The generator's options for a plan's scene trials: its `generate` block (sensor
/// resolution, views, ground filter; white: no ground filter, no colours), the rest the
/// generator's defaults. Throws core::Error as sim::validate does.
sim::GenerateOptions sceneGenerateOptions(const Plan& plan);

class StudySource : public viewer::TrialSource {
  public:
    /// Loads every scene and candidates file of the plan now, so a bad one fails before
    /// the window opens (core::Error naming it). `order` from trialOrder(); `first`: the
    /// trials of the study already run (a resumed session, numberOffset()). Without
    /// `with_candidates` no candidates file is read and no detector runs: every trial
    /// shows none (a replay takes the boxes shown from the study folder).
    StudySource(const Plan& plan, std::vector<int> order, int first = 0, bool with_candidates = true);
    ~StudySource() override;

    int count() const override { return static_cast<int>(order_.size()); }
    int numberOffset() const override { return first_; }
    viewer::TrialSetup begin(int trial, viewer::CloudFeed& feed) override;
    /// Joins the trial's generator (a scene still generating is finished first).
    void end(int trial) override;
    std::vector<viewer::Question> questions(int gap) override {
        return gap >= 0 && static_cast<std::size_t>(gap) < questions_.size() ? questions_[static_cast<std::size_t>(gap)]
                                                                             : std::vector<viewer::Question>{};
    }
    /// The questions of each gap of this run (questions()).
    void setQuestions(std::vector<std::vector<viewer::Question>> by_gap) { questions_ = std::move(by_gap); }
    /// The candidate boxes plan trial `plan_trial` (an index into the plan's trials) shows:
    /// its candidates file's, or its condition's detector's.
    const std::vector<core::Candidate>& candidatesOf(std::size_t plan_trial) const { return candidates_[plan_trial]; }
    /// The plan's trial that runs at position `trial`.
    const PlanTrial& planTrial(int trial) const { return plan_.trials[static_cast<std::size_t>(order_[trial])]; }
    /// Cloud trials that start in above-ground colours get their terrain from `start`.
    /// `run_colour`: the colours the run starts in (--colour), which a trial whose
    /// condition sets none keeps unless an earlier trial's condition changed them.
    void setTerrain(TerrainStarter start, viewer::ColourMode run_colour) {
        start_terrain_ = std::move(start);
        run_colour_ = run_colour;
    }
    /// The colours trial `trial` starts in as far as the plan knows them (the operator's
    /// colour key aside): its condition's, else the last earlier trial's that set some,
    /// else the run's.
    viewer::ColourMode startColour(int trial) const;

  private:
    void join();

    Plan plan_;
    std::vector<int> order_;
    int first_ = 0;
    std::vector<std::shared_ptr<const core::Scene>> scenes_;  // per plan trial (null: cloud)
    std::vector<std::vector<core::Candidate>> candidates_;    // per plan trial
    std::vector<std::vector<viewer::Question>> questions_;
    std::thread generator_;
    TerrainStarter start_terrain_;
    viewer::ColourMode run_colour_ = viewer::ColourMode::File;
    CloudTerrain terrain_;  // the trial in flight's
};

}  // namespace study
