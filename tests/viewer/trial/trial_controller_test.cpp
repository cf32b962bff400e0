// tests/viewer/trial/trial_controller_test.cpp: the trials of a run without a window: the
// ready screen, the decisions (designate, reject, confirm, no target, the time limit),
// what the observer hears and the decisions log.
#include "trial/trial_controller.hpp"

#include "trial_fakes.hpp"

#include <doctest/doctest.h>

#include <memory>
#include <vector>

using namespace viewer;
using viewer::test::FakeTrialObserver;
using viewer::test::FakeTrialSource;

namespace {

/// A pointer whose ray from 10 m above meets the one point at `local` (a target's).
struct PointerAt {
    explicit PointerAt(const glm::dvec3& local) : pointer(PickOptions{}) {
        core::CloudPoint p;
        p.position = glm::vec3(local);
        p.label = core::Role::Target;
        const std::vector<core::CloudPoint> points{p};
        auto picks = std::make_shared<PickSet>();
        picks->add(std::make_shared<PickIndex>(points));
        set = picks;
        pointer.setIndex(picks);
        pointer.update(LocalRay{local + glm::dvec3(0.0, 0.0, 10.0), glm::dvec3(0.0, 0.0, -1.0)});
    }
    PointerTool pointer;
    std::shared_ptr<const PickSet> set;
};

OperatorInput pressed(bool OperatorInput::* key) {
    OperatorInput in;
    in.*key = true;
    return in;
}

}  // namespace

TEST_CASE("a trial waits on its ready screen for its cloud and the operator, then runs") {
    RunLog log;
    FakeTrialSource source;
    FakeTrialObserver observer;
    TrialController trials(&source, &observer, log, true);
    CHECK(trials.study());
    CHECK(trials.total() == 2);
    trials.begin(0);
    CHECK(source.began == std::vector<int>{0});
    CHECK(trials.readyScreen());
    CHECK(trials.setup().name == "trial 0");
    CHECK_FALSE(trials.running());
    // Nothing starts it while the cloud is not ready, nor without the operator's next.
    CHECK(trials.handleReadyScreen(pressed(&OperatorInput::next), false, 1));
    CHECK(trials.handleReadyScreen(OperatorInput{}, true, 2));
    CHECK(trials.readyScreen());
    CHECK(observer.calls.empty());
    CHECK(trials.handleReadyScreen(pressed(&OperatorInput::next), true, 3));
    CHECK_FALSE(trials.readyScreen());
    CHECK(trials.running());
    CHECK(observer.calls == std::vector<std::string>{"start 0"});
    CHECK(trials.decisions().back() == nlohmann::json{{"frame", 3}, {"action", "start"}, {"trial", 0}});
    // Off the ready screen the controller leaves the input to the others.
    CHECK_FALSE(trials.handleReadyScreen(pressed(&OperatorInput::next), true, 4));
    // The next trial ends the source's last one first.
    trials.begin(1);
    CHECK(source.ended == std::vector<int>{0});
    CHECK(trials.index() == 1);
    CHECK(trials.readyScreen());
}

TEST_CASE("a designation is recorded, confirmed, and ends the trial with its distance to the target") {
    RunLog log;
    FakeTrialSource source;
    FakeTrialObserver observer;
    TrialController trials(&source, &observer, log, true);
    trials.begin(0);
    trials.handleReadyScreen(pressed(&OperatorInput::next), true, 1);
    const glm::dvec3 origin(1000.0, 2000.0, 0.0);
    CandidatesTool candidates;

    // Nothing picked: the designation is recorded as none.
    PointerTool idle{PickOptions{}};
    trials.decide(pressed(&OperatorInput::designate), {2, origin, &idle, &candidates, nullptr});
    CHECK(trials.decisions().back() ==
          nlohmann::json{{"frame", 2}, {"action", "designate"}, {"trial", 0}, {"world", nullptr}});
    CHECK_FALSE(trials.designated());

    const glm::dvec3 local(3.0, 4.0, 5.0);
    PointerAt at(local);
    REQUIRE(at.pointer.hit());
    const TrialContext c{5, origin, &at.pointer, &candidates, at.set.get()};
    trials.decide(pressed(&OperatorInput::designate), c);
    REQUIRE(trials.designated());
    CHECK(glm::length(*trials.designated() - local) < 1e-6);
    const nlohmann::json& designate = trials.decisions().back();
    CHECK(designate["action"] == "designate");
    CHECK(designate["label"] == "target");
    CHECK(designate["world"][0].get<double>() == doctest::Approx(1003.0));
    REQUIRE(observer.designated.size() == 1);
    CHECK(glm::length(observer.designated[0] - (local + origin)) < 1e-6);

    trials.decide(pressed(&OperatorInput::confirm), c);
    CHECK_FALSE(trials.running());
    CHECK(observer.calls == std::vector<std::string>{"start 0", "designate 0", "end 0 confirm"});
    CHECK(observer.outcome.decision == Decision::Confirm);
    CHECK(observer.outcome.designations == 1);
    CHECK(observer.outcome.target_known);
    REQUIRE(observer.outcome.target_distance_m);
    CHECK(*observer.outcome.target_distance_m < 1e-6);
    // The centre of the target points' bounds, in world coordinates (a candidate box
    // holding it holds the target).
    REQUIRE(observer.outcome.target_centre_world);
    CHECK(glm::length(*observer.outcome.target_centre_world - (local + origin)) < 1e-4);
    CHECK(trials.decisions().back() ==
          nlohmann::json{{"trial", 0}, {"frame", 5}, {"action", "end"}, {"decision", "confirm"}});
    // Ending again does nothing.
    trials.end(Decision::Quit, c);
    CHECK(observer.calls.size() == 3);
}

TEST_CASE("rejecting the box pointed at, no target, and the time limit") {
    RunLog log;
    FakeTrialSource source;
    FakeTrialObserver observer;
    TrialController trials(&source, &observer, log, true);
    std::vector<core::Candidate> boxes(2);
    boxes[0].id = "near";
    boxes[0].centre_world = {10.0, 0.0, 0.0};
    boxes[0].size_m = {2.0, 2.0, 2.0};
    boxes[1].id = "far";
    boxes[1].centre_world = {50.0, 50.0, 0.0};
    boxes[1].size_m = {2.0, 2.0, 2.0};
    CandidatesTool candidates;
    candidates.set(boxes, glm::dvec3(0.0));
    candidates.update(LocalRay{glm::dvec3(0.0), glm::dvec3(1.0, 0.0, 0.0)});
    PointerTool pointer{PickOptions{}};
    const TrialContext c{1, glm::dvec3(0.0), &pointer, &candidates, nullptr};

    trials.begin(0);
    trials.handleReadyScreen(pressed(&OperatorInput::next), true, 1);
    trials.decide(pressed(&OperatorInput::reject), c);
    CHECK(candidates.verdict(0) == Verdict::Rejected);
    CHECK(trials.decisions().back()["candidate"] == "near");
    trials.decide(pressed(&OperatorInput::no_target), c);
    CHECK_FALSE(trials.running());
    // The box never reviewed is reported before the end.
    CHECK(observer.calls == std::vector<std::string>{"start 0", "verdict 0 near rejected", "verdict 0 far unreviewed",
                                                     "end 0 no_target"});
    CHECK_FALSE(observer.outcome.target_known);

    // A limit already past: the first decision of the running trial ends it as a timeout.
    source.setup.time_limit_s = 1e-9;
    trials.begin(1);
    trials.handleReadyScreen(pressed(&OperatorInput::next), true, 2);
    trials.decide(OperatorInput{}, c);
    CHECK_FALSE(trials.running());
    CHECK(observer.outcome.decision == Decision::Timeout);
}

TEST_CASE("a plain run is one trial without a ready screen: its decisions carry no trial") {
    RunLog log;
    TrialController trials(nullptr, nullptr, log, true);
    CHECK_FALSE(trials.study());
    CHECK(trials.index() == -1);
    CHECK_FALSE(trials.readyScreen());
    CHECK_FALSE(trials.handleReadyScreen(pressed(&OperatorInput::next), true, 1));
    CHECK(trials.questions(0).empty());
    CandidatesTool candidates;
    PointerTool pointer{PickOptions{}};
    trials.decide(pressed(&OperatorInput::no_target), {4, glm::dvec3(0.0), &pointer, &candidates, nullptr});
    CHECK(trials.decisions() == nlohmann::json::array({{{"frame", 4}, {"action", "no_target"}}}));
    // Candidates go in once, when the origin is final.
    CHECK_FALSE(trials.placeCandidates(false));
    CHECK(trials.placeCandidates(true));
    CHECK_FALSE(trials.placeCandidates(true));
}

TEST_CASE("withdrawing a designation is reported, and a replay's marks designate, withdraw and judge boxes") {
    RunLog log;
    FakeTrialSource source;
    FakeTrialObserver observer;
    TrialController trials(&source, &observer, log, true);
    trials.begin(0);
    trials.handleReadyScreen(pressed(&OperatorInput::next), true, 1);
    const glm::dvec3 local(3.0, 4.0, 5.0);
    PointerAt at(local);
    CandidatesTool none;
    const TrialContext c{2, glm::dvec3(0.0), &at.pointer, &none, at.set.get()};
    trials.decide(pressed(&OperatorInput::designate), c);
    trials.decide(pressed(&OperatorInput::reject), c);  // no box pointed at: withdrawn
    CHECK_FALSE(trials.designated());
    CHECK(observer.calls == std::vector<std::string>{"start 0", "designate 0", "withdraw 0"});

    // A replay (a plain run): the recorded marks, as the operator made them.
    RunLog replay_log;
    TrialController replay(nullptr, nullptr, replay_log, true);
    std::vector<core::Candidate> boxes(1);
    boxes[0].id = "c1";
    boxes[0].size_m = {2.0, 2.0, 2.0};
    CandidatesTool candidates;
    const glm::dvec3 origin(1000.0, 0.0, 0.0);
    candidates.set(boxes, origin);
    PointerTool idle{PickOptions{}};
    const TrialContext rc{7, origin, &idle, &candidates, nullptr};
    TrialMark designate;
    designate.t_s = 1.5;
    designate.designated_world = glm::dvec3(1003.0, 4.0, 5.0);
    replay.replayMark(designate, rc);
    REQUIRE(replay.designated());
    CHECK(glm::length(*replay.designated() - glm::dvec3(3.0, 4.0, 5.0)) < 1e-9);
    CHECK(replay.decisions().back()["action"] == "designate");
    CHECK(replay.decisions().back()["source"] == "replay");
    TrialMark verdict;
    verdict.t_s = 2.0;
    verdict.candidate = "c1";
    verdict.verdict = Verdict::Rejected;
    replay.replayMark(verdict, rc);
    CHECK(candidates.verdict(0) == Verdict::Rejected);
    CHECK(replay.decisions().back()["candidate"] == "c1");
    replay.replayMark(TrialMark{}, rc);  // a withdrawn designation
    CHECK_FALSE(replay.designated());
}

TEST_CASE("the designation is marked by a thin cross sized in the world, not a screen-sized dot") {
    RunLog log;
    TrialController trials(nullptr, nullptr, log, true);
    CandidatesTool candidates;
    PointerTool idle{PickOptions{}};
    TrialMark mark;
    mark.designated_world = glm::dvec3(3.0, 4.0, 5.0);
    trials.replayMark(mark, {1, glm::dvec3(0.0), &idle, &candidates, nullptr});
    for (const double scale : {1.0, 4.0}) {
        OverlayList out;
        trials.draw(out, scale);
        CHECK(out.dots.empty());  // a dot is a square of fixed pixels: it covers the target in a headset
        REQUIRE(out.lines.size() == 6);
        for (std::size_t i = 0; i < 6; i += 2)
            CHECK(glm::length(out.lines[i + 1].local - out.lines[i].local) == doctest::Approx(2.0 / scale));
    }
}
