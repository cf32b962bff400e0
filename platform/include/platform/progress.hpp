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
    void finish();

  private:
    void draw(bool final);
    std::string label_;
    std::size_t total_, done_ = 0;
    bool enabled_, finished_ = false;
    std::chrono::steady_clock::time_point start_, last_draw_;
};

}  // namespace platform
