// viewer/src/input/replay_player.cpp: a trace's samples in real time.
#include "input/replay_player.hpp"

namespace viewer {

OperatorInput ReplayPlayer::take(bool loaded, Clock::time_point now) {
    OperatorInput in;
    if (trace_.empty()) return in;
    if (done_) {
        in.replay_done = true;
    } else if (loaded) {
        if (!start_) start_ = now;
        const double t = trace_.front().t_s + std::chrono::duration<double>(now - *start_).count();
        while (next_ < trace_.size() && trace_[next_].t_s <= t) ++next_;
        shown_ = trace_[next_ == 0 ? 0 : next_ - 1];
        if (next_ >= trace_.size()) done_ = true;  // the last sample is shown once
        while (next_mark_ < marks_.size() && (done_ || marks_[next_mark_].t_s <= t))
            in.replay_marks.push_back(marks_[next_mark_++]);
    }
    in.replay = shown_;
    return in;
}

}  // namespace viewer
