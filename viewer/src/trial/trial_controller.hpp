// viewer/src/trial/trial_controller.hpp: the trials of a run (viewer/trial.hpp): which trial is
// up, its ready screen, its start and its end, the operator's decisions (designate,
// confirm, reject, no target, the time limit) and the run log's record of them. A plain
// `view` run is one trial without a ready screen or an observer (index -1).
#pragma once
#include "input/operator_input.hpp"
#include "ui/overlay_renderer.hpp"
#include "ui/panel.hpp"
#include "run_log.hpp"
#include "tools/candidates_tool.hpp"
#include "tools/pointer_tool.hpp"

#include <viewer/cloud_feed.hpp>
#include <viewer/cloud_feed_source.hpp>
#include <viewer/trial.hpp>

#include <nlohmann/json.hpp>

#include <chrono>
#include <memory>
#include <optional>

namespace viewer {

/// What the controller reads of the frame when it acts.
struct TrialContext {
    long frame = 0;
    glm::dvec3 origin{0.0};  // world coordinates of the local frame
    const PointerTool* pointer = nullptr;
    CandidatesTool* candidates = nullptr;
    const PickSet* picks = nullptr;  // null until picking is ready
};

class TrialController {
  public:
    using Clock = std::chrono::steady_clock;
    /// `source` and `observer` null: a plain run.
    TrialController(TrialSource* source, TrialObserver* observer, RunLog& log, bool quiet);

    bool study() const { return source_ != nullptr; }
    int index() const { return index_; }
    int total() const { return total_; }
    const TrialSetup& setup() const { return setup_; }
    bool readyScreen() const { return ready_screen_; }
    /// Seconds the ready screen must still stay up (its break, TrialSetup::min_ready_s); 0
    /// when it may be dismissed or is not up.
    double breakLeft() const;
    bool running() const { return running_; }
    /// Seconds since the trial started (0 unless running).
    double time() const;
    const std::optional<glm::dvec3>& designated() const { return designated_local_; }

    /// Ends the previous trial's feed, then starts trial `index` on its ready screen with a
    /// fresh feed (LOD order on the loader's thread). Returns the trial's point source.
    PointSource& begin(int index);
    /// On the ready screen: a `next` while `ready` starts the trial. Returns whether the
    /// ready screen was up (nothing else acts on it then).
    bool handleReadyScreen(const OperatorInput& in, bool ready, long frame);
    /// Designate, reject, confirm, no target, and the time limit.
    void decide(const OperatorInput& in, const TrialContext& c);
    /// A replay's recorded mark (TrialMark): the designation set or withdrawn, or a
    /// candidate's verdict, shown as the operator made it and recorded in the decisions
    /// log with "source": "replay". Reports nothing to the observer.
    void replayMark(const TrialMark& mark, const TrialContext& c);
    /// Ends the running trial (nothing when none runs) and reports it.
    void end(Decision decision, const TrialContext& c);
    /// The source's questions at gap `gap` of the run (TrialSource::questions).
    std::vector<Question> questions(int gap) const {
        return source_ ? source_->questions(gap) : std::vector<Question>{};
    }
    /// Reports an answer to the observer and the decisions log ({"action": "answer", "gap",
    /// "question", "response", "skipped", "source"}).
    void answered(int gap, int question, const Answer& answer, const char* source, long frame);
    /// The ready screen's break counts again from now (it came up under a questionnaire).
    void restartReadyClock() { ready_since_ = Clock::now(); }
    /// After the run: the source's end of the last trial.
    void finish();

    /// Hands the running trial's observer a frame of its trace.
    void observeFrame(const TraceSample& sample) const {
        if (observer_ && running_) observer_->onFrame(index_, sample);
    }
    /// The trial's part of the panels: index, count, name, time, limit, ready screen, designation.
    void describe(PanelFrame& p) const;
    void countModeSwitch() {
        if (running_) ++outcome_.mode_switches;
    }
    void addFreeModeSeconds(double dt) {
        if (running_) outcome_.seconds_in_free_mode += dt;
    }
    /// Appends {"frame", "action", "trial"?, ...extra} to the decisions log.
    void record(const char* action, long frame, nlohmann::json extra = nlohmann::json::object());
    /// The designated point: a thin cross 2 m wide at life size (lines in the world, no
    /// screen-sized dot), on the desktop and in the headset alike.
    void draw(OverlayList& out, double scale) const;
    const nlohmann::json& decisions() const { return decisions_; }
    /// The trial's above-ground terrain was bound (`source`, ViewTerrain::source) or will
    /// not come (`failure`): kept in its outcome, and an event of the run log in a study.
    void noteTerrain(const std::string& source, const std::string& failure);
    /// Candidates go in once the source's origin is final (PointSource::originFinal); true once.
    bool placeCandidates(bool origin_final);

  private:
    TrialSource* source_ = nullptr;
    TrialObserver* observer_ = nullptr;
    RunLog* log_ = nullptr;
    bool quiet_ = false;
    int index_ = -1, total_ = 1;
    int offset_ = 0;  // the source's numberOffset(): trials run before this run
    TrialSetup setup_;
    std::unique_ptr<CloudFeedSource> points_;  // before the feed: it points into it
    std::unique_ptr<CloudFeed> feed_;
    bool ready_screen_ = false;  // waiting for the operator to start
    bool running_ = false;       // between the ready screen and the decision
    Clock::time_point started_{};
    Clock::time_point ready_since_{};  // when the ready screen came up
    TrialOutcome outcome_;
    std::optional<glm::dvec3> designated_local_;
    bool candidates_placed_ = false;
    nlohmann::json decisions_ = nlohmann::json::array();
};

}  // namespace viewer
