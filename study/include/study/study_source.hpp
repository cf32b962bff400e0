// study/study_source.hpp: a plan's trials for the viewer (viewer::TrialSource): each
// trial's cloud file is opened through viewer::openPointSource and streamed whole into
// the viewer's feed for that trial (a COPC file too: hits are judged against every target
// point), or its scene's cloud is generated on a worker thread into that feed.
#pragma once
#include <study/plan.hpp>
#include <viewer/trial.hpp>

#include <core/candidates.hpp>
#include <core/scene.hpp>

#include <memory>
#include <thread>
#include <vector>

namespace sim {
struct GenerateOptions;  // sim/generator.hpp
}

namespace study {

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

  private:
    void join();

    Plan plan_;
    std::vector<int> order_;
    int first_ = 0;
    std::vector<std::shared_ptr<const core::Scene>> scenes_;  // per plan trial (null: cloud)
    std::vector<std::vector<core::Candidate>> candidates_;    // per plan trial
    std::vector<std::vector<viewer::Question>> questions_;
    std::thread generator_;
};

}  // namespace study
