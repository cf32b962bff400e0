// platform/progress.hpp: a progress bar on stderr when it is a terminal, silent otherwise.
#pragma once
#include <chrono>
#include <cstddef>
#include <string>

namespace platform {

class Progress {
  public:
    /// `label` is shown before the bar; `total` units of work. Draws only if stderr is a tty
    /// (or force is true), at most ~10 times a second.
    Progress(std::string label, std::size_t total, bool force = false);
    ~Progress();
    /// Thread-safe enough for one caller; call from the coordinating thread.
    void advance(std::size_t units = 1);
    /// Draws the final 100 % line (once). The destructor calls it, except while an
    /// exception unwinds the work: then the bar ends its line where the work stopped,
    /// so the error that follows starts a line of its own and no failed run shows 100 %.
    void finish();

  private:
    void draw(bool final);
    std::string label_;
    std::size_t total_, done_ = 0;
    bool enabled_, finished_ = false;
    int exceptions_at_start_ = 0;  // std::uncaught_exceptions() when made
    std::chrono::steady_clock::time_point start_, last_draw_;
};

}  // namespace platform
