// viewer/src/trial/trial_controller.cpp: trial state, decisions and their record.
#include "trial/trial_controller.hpp"

#include <core/scene.hpp>

#include <algorithm>
#include <cstdio>

namespace viewer {

namespace {
nlohmann::json vec(const glm::dvec3& v) { return {v.x, v.y, v.z}; }
}  // namespace

TrialController::TrialController(TrialSource* source, TrialObserver* observer, RunLog& log, bool quiet)
    : source_(source), observer_(observer), log_(&log), quiet_(quiet) {
    if (source_) {
        offset_ = source_->numberOffset();
        total_ = source_->count();
    }
}

double TrialController::time() const {
    if (!running_) return 0.0;
    return std::chrono::duration<double>(Clock::now() - started_).count();
}

double TrialController::breakLeft() const {
    if (!ready_screen_ || setup_.min_ready_s <= 0.0) return 0.0;
    return std::max(0.0, setup_.min_ready_s - std::chrono::duration<double>(Clock::now() - ready_since_).count());
}

PointSource& TrialController::begin(int index) {
    if (index_ >= 0) source_->end(index_);  // before its feed goes
    points_.reset();
    feed_ = std::make_unique<CloudFeed>();
    feed_->enableLodOrder();
    points_ = std::make_unique<CloudFeedSource>(*feed_);
    index_ = index;
    ready_screen_ = true;
    running_ = false;
    outcome_ = TrialOutcome{};
    designated_local_.reset();
    candidates_placed_ = false;
    setup_ = source_->begin(index, *feed_);
    ready_since_ = Clock::now();
    log_->event("trial " + std::to_string(index) + ": ready screen (" + setup_.name + ")");
    if (!quiet_)
        std::fprintf(stderr, "ladarvr: study: trial %d of %d (%s): ready screen\n", offset_ + index + 1,
                     offset_ + total_, setup_.name.c_str());
    return *points_;
}

void TrialController::noteTerrain(const std::string& source, const std::string& failure) {
    if (!source_ || index_ < 0) return;
    outcome_.terrain_source = source;
    outcome_.terrain_failure = failure;
    log_->event("trial " + std::to_string(index_) + ": " +
                (source.empty() ? "no terrain: " + failure : "above-ground colours from " + source));
}

void TrialController::finish() {
    if (source_ && index_ >= 0) source_->end(index_);
}

bool TrialController::placeCandidates(bool origin_final) {
    if (candidates_placed_ || !origin_final) return false;
    candidates_placed_ = true;
    return true;
}

void TrialController::record(const char* action, long frame, nlohmann::json extra) {
    extra["frame"] = frame;
    extra["action"] = action;
    if (index_ >= 0) extra["trial"] = index_;
    decisions_.push_back(std::move(extra));
}

bool TrialController::handleReadyScreen(const OperatorInput& in, bool ready, long frame) {
    if (!ready_screen_) return false;
    if (in.next && ready && breakLeft() <= 0.0) {
        ready_screen_ = false;
        running_ = true;
        started_ = Clock::now();
        if (observer_) observer_->onStart(index_);
        record("start", frame,
               setup_.min_ready_s > 0.0
                   ? nlohmann::json{{"ready_screen_s", std::chrono::duration<double>(started_ - ready_since_).count()}}
                   : nlohmann::json::object());
        if (!quiet_) std::fprintf(stderr, "ladarvr: study: trial %d started\n", offset_ + index_ + 1);
    }
    return true;
}

void TrialController::answered(int gap, int question, const Answer& answer, const char* source, long frame) {
    if (observer_) observer_->onAnswer(gap, question, answer);
    decisions_.push_back({{"frame", frame},
                          {"action", "answer"},
                          {"gap", gap},
                          {"question", question},
                          {"response", answer.response},
                          {"skipped", answer.skipped},
                          {"source", source}});
}

void TrialController::decide(const OperatorInput& in, const TrialContext& c) {
    const double t_s = time();
    const PointerTool& pointer = *c.pointer;
    CandidatesTool& candidates = *c.candidates;
    if (in.designate) {
        if (pointer.hit()) {
            designated_local_ = pointer.hit()->local;
            const glm::dvec3 w = pointer.hit()->local + c.origin;
            if (running_) {
                ++outcome_.designations;
                if (!outcome_.time_to_first_designation_s) outcome_.time_to_first_designation_s = t_s;
                if (observer_) observer_->onDesignate(index_, t_s, w);
            }
            nlohmann::json what = {{"world", vec(w)}, {"label", std::string(core::roleName(pointer.hit()->label))}};
            // A source of levels (an octree): the level of the node the point was picked from.
            if (pointer.hit()->level >= 0) what["level"] = pointer.hit()->level;
            record("designate", c.frame, std::move(what));
        } else {
            record("designate", c.frame, {{"world", nullptr}});
        }
    }
    if (in.reject) {
        if (const auto i = candidates.decide(Verdict::Rejected)) {
            if (observer_ && running_) observer_->onVerdict(index_, t_s, candidates.candidate(*i), Verdict::Rejected);
            record("reject", c.frame, {{"candidate", candidates.candidate(*i).id}});
        } else {
            if (designated_local_ && running_ && observer_) observer_->onWithdraw(index_, t_s);
            designated_local_.reset();
            record("reject", c.frame, {{"candidate", nullptr}});
        }
    }
    if (in.confirm) {
        if (const auto i = candidates.decide(Verdict::Confirmed)) {
            // Confirming a candidate confirms it as the target: the trial ends with the
            // designation made, else the pointer's hit, else the box's centre.
            if (observer_ && running_) observer_->onVerdict(index_, t_s, candidates.candidate(*i), Verdict::Confirmed);
            record("confirm", c.frame, {{"candidate", candidates.candidate(*i).id}});
            if (!designated_local_)
                designated_local_ =
                    pointer.hit() ? pointer.hit()->local : candidates.candidate(*i).centre_world - c.origin;
            end(Decision::Confirm, c);
        } else if (designated_local_) {
            record("confirm", c.frame, {{"world", vec(*designated_local_ + c.origin)}});
            end(Decision::Confirm, c);
        } else {
            record("confirm", c.frame, {{"world", nullptr}});
        }
    }
    if (in.no_target) {
        record("no_target", c.frame);
        if (running_) end(Decision::NoTarget, c);
    }
    if (running_ && setup_.time_limit_s > 0.0 && time() >= setup_.time_limit_s) end(Decision::Timeout, c);
}

void TrialController::replayMark(const TrialMark& mark, const TrialContext& c) {
    if (!mark.candidate.empty()) {
        c.candidates->setVerdict(mark.candidate, mark.verdict);
        record(mark.verdict == Verdict::Confirmed ? "confirm" : "reject", c.frame,
               {{"candidate", mark.candidate}, {"t_s", mark.t_s}, {"source", "replay"}});
    } else if (mark.designated_world) {
        designated_local_ = *mark.designated_world - c.origin;
        record("designate", c.frame, {{"world", vec(*mark.designated_world)}, {"t_s", mark.t_s}, {"source", "replay"}});
    } else {
        designated_local_.reset();
        record("reject", c.frame, {{"candidate", nullptr}, {"t_s", mark.t_s}, {"source", "replay"}});
    }
}

void TrialController::end(Decision decision, const TrialContext& c) {
    if (!running_) return;
    running_ = false;
    TrialOutcome& o = outcome_;
    o.decision = decision;
    o.time_to_decision_s = std::chrono::duration<double>(Clock::now() - started_).count();
    o.target_known = c.picks && c.picks->hasTargets();
    if (c.picks)
        if (const auto centre = c.picks->targetCentre()) o.target_centre_world = *centre + c.origin;
    if (designated_local_) {
        o.designated_world = *designated_local_ + c.origin;
        if (c.picks) o.target_distance_m = c.picks->nearestTargetDistance(*designated_local_);
    }
    if (observer_) {
        const CandidatesTool& candidates = *c.candidates;
        for (std::size_t i = 0; i < candidates.size(); ++i)
            if (candidates.verdict(i) == Verdict::Unreviewed)
                observer_->onVerdict(index_, o.time_to_decision_s, candidates.candidate(i), Verdict::Unreviewed);
        observer_->onEnd(index_, o);
    }
    decisions_.push_back(
        {{"trial", index_}, {"frame", c.frame}, {"action", "end"}, {"decision", decisionName(decision)}});
    log_->event("trial " + std::to_string(index_) + ": " + decisionName(decision));
    if (!quiet_)
        std::fprintf(stderr, "ladarvr: study: trial %d ended: %s after %.1f s\n", offset_ + index_ + 1,
                     decisionName(decision), o.time_to_decision_s);
}

void TrialController::describe(PanelFrame& p) const {
    p.trial = offset_ + index_;
    p.trials = offset_ + total_;
    p.trial_name = setup_.name;
    p.trial_s = time();
    p.time_limit_s = setup_.time_limit_s;
    p.ready_screen = ready_screen_;
    p.break_left_s = breakLeft();
    p.designated_local = designated_local_;
}

void TrialController::draw(OverlayList& out, double scale) const {
    if (!designated_local_) return;
    // Lines only, sized in the world: a dot is a square of fixed pixels, which in a
    // headset's eye image (fewer pixels over a wider view than the desktop's) covers the
    // target it marks.
    const glm::vec4 colour(1.0f, 0.2f, 1.0f, 1.0f);
    const glm::dvec3 c = *designated_local_;
    const double r = 1.0 / scale;  // a 2 m cross at life size
    out.line(c - glm::dvec3(r, 0, 0), c + glm::dvec3(r, 0, 0), colour);
    out.line(c - glm::dvec3(0, r, 0), c + glm::dvec3(0, r, 0), colour);
    out.line(c - glm::dvec3(0, 0, r), c + glm::dvec3(0, 0, r), colour);
}

}  // namespace viewer
