// tests/viewer/input/replay_player_test.cpp: a trace played in real time
// (viewer/src/input/replay_player.cpp): nothing before the cloud is loaded, then the sample
// due at each time, the recorded marks as their times come, and the end.
#include "input/replay_player.hpp"

#include <doctest/doctest.h>

#include <vector>

using namespace viewer;

TEST_CASE("replay player: samples and marks by time from the first loaded frame") {
    std::vector<TraceSample> trace(3);
    trace[0].t_s = 0.0;
    trace[1].t_s = 1.0;
    trace[2].t_s = 2.0;
    std::vector<TrialMark> marks(3);
    marks[0].t_s = 0.5;
    marks[0].designated_world = glm::dvec3(1.0, 2.0, 3.0);
    marks[1].t_s = 1.5;
    marks[1].candidate = "c1";
    marks[1].verdict = Verdict::Rejected;
    marks[2].t_s = 9.0;  // after the last sample: given with it
    ReplayPlayer p(trace, marks);
    using namespace std::chrono_literals;
    const ReplayPlayer::Clock::time_point t0{};
    CHECK_FALSE(p.take(false, t0).replay);  // the cloud is still loading
    OperatorInput in = p.take(true, t0);
    REQUIRE(in.replay);
    CHECK(in.replay->t_s == 0.0);
    CHECK(in.replay_marks.empty());
    in = p.take(true, t0 + 600ms);
    REQUIRE(in.replay_marks.size() == 1);
    CHECK(*in.replay_marks[0].designated_world == glm::dvec3(1.0, 2.0, 3.0));
    CHECK(p.take(true, t0 + 700ms).replay_marks.empty());  // each mark once
    in = p.take(true, t0 + 1600ms);
    CHECK(in.replay->t_s == 1.0);
    REQUIRE(in.replay_marks.size() == 1);
    CHECK(in.replay_marks[0].candidate == "c1");
    in = p.take(true, t0 + 2100ms);
    CHECK(in.replay->t_s == 2.0);
    REQUIRE(in.replay_marks.size() == 1);
    CHECK(in.replay_marks[0].t_s == 9.0);
    CHECK_FALSE(in.replay_done);
    CHECK(p.take(true, t0 + 2200ms).replay_done);
}
