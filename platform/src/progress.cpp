// Kept our own: Debian packages no C++ progress-bar library, and this throttled, tty-only bar is 50 lines.
// progress: a one-line bar on stderr, redrawn at most ~10 times a second.
#include <platform/progress.hpp>

#include <algorithm>
#include <cstdio>
#include <exception>

#include <unistd.h>

namespace platform {

Progress::Progress(std::string label, std::size_t total, bool force)
    : label_(std::move(label)),
      total_(total),
      enabled_(force || ::isatty(STDERR_FILENO) == 1),
      exceptions_at_start_(std::uncaught_exceptions()),
      start_(std::chrono::steady_clock::now()),
      last_draw_(start_) {
    if (enabled_) draw(false);
}

Progress::~Progress() {
    if (finished_) return;
    if (std::uncaught_exceptions() > exceptions_at_start_) {
        finished_ = true;
        if (enabled_) draw(true);  // where the work stopped, with its newline
        return;
    }
    finish();
}

void Progress::advance(std::size_t units) {
    done_ = std::min(total_, done_ + units);
    if (!enabled_ || finished_) return;
    const auto now = std::chrono::steady_clock::now();
    // The final 100 % line is finish()'s (or the destructor's).
    if (now - last_draw_ >= std::chrono::milliseconds(100) && done_ < total_) {
        last_draw_ = now;
        draw(false);
    }
}

void Progress::finish() {
    if (finished_) return;
    finished_ = true;
    if (enabled_) {
        done_ = total_;
        draw(true);
    }
}

void Progress::draw(bool final) {
    constexpr int kWidth = 30;
    const double fraction = total_ == 0 ? 1.0 : double(done_) / double(total_);
    const int filled = std::clamp(int(fraction * kWidth + 0.5), 0, kWidth);
    const double elapsed_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    char bar[kWidth + 1];
    for (int i = 0; i < kWidth; ++i) bar[i] = i < filled ? '#' : '.';
    bar[kWidth] = '\0';
    std::fprintf(stderr, "\r%s [%s] %3d%% %6.1f s%s", label_.c_str(), bar, int(fraction * 100.0 + 0.5), elapsed_s,
                 final ? "\n" : "");
    std::fflush(stderr);
}

}  // namespace platform
