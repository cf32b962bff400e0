// viewer/src/input/replay_player.hpp: a recorded trace (--replay) played back in real time
// as operator input: the sample to show each frame (head pose, zoom, mode, pointer hit)
// and the operator's recorded marks (designations, verdicts) as their times come.
#pragma once
#include "input/operator_input.hpp"

#include <chrono>
#include <cstddef>
#include <optional>
#include <span>

namespace viewer {

class ReplayPlayer {
  public:
    using Clock = std::chrono::steady_clock;
    /// Plays `trace` and `marks` (by time), borrowed: the samples (the viewer's options)
    /// outlive the player, so a long trace is held once.
    explicit ReplayPlayer(std::span<const TraceSample> trace, std::span<const TrialMark> marks = {})
        : trace_(trace), marks_(marks) {}
    /// Nothing until `loaded` (the cloud is whole); then the sample due at `now` counted
    /// from the first loaded frame, with the marks whose time has come since the last call
    /// (all that are left with the last sample). The last sample is shown once; the call
    /// after it reports replay_done (and keeps showing it). An empty trace gives nothing.
    OperatorInput take(bool loaded, Clock::time_point now);

  private:
    std::span<const TraceSample> trace_;
    std::span<const TrialMark> marks_;
    std::size_t next_mark_ = 0;
    std::optional<Clock::time_point> start_;
    std::optional<TraceSample> shown_;
    std::size_t next_ = 0;
    bool done_ = false;
};

}  // namespace viewer
