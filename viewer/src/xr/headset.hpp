// viewer/src/xr/headset.hpp: the OpenXR session's life as the frame loop sees it: started at
// setup when a runtime answers, its events polled each frame, and the drop to the desktop
// mode (logged once, with its reason and frame) when it cannot start, is lost or fails.
#pragma once
#include "run_log.hpp"
#include "xr/xr_session.hpp"

#include <memory>
#include <string>

struct GLFWwindow;

namespace viewer {

class Headset {
  public:
    Headset(RunLog& log, bool quiet) : log_(&log), quiet_(quiet) {}
    /// Tries OpenXR on `window` (unless `use_xr` is false); falls back to the desktop
    /// with the reason when it cannot start. Never throws.
    void start(GLFWwindow* window, bool use_xr);
    /// Drops the session: the desktop mode from frame `frame` on.
    void fallBack(const std::string& reason, long frame);
    /// Runs the session's events. Returns false when the loop should leave now (the
    /// session ended or was lost while `quitting`).
    bool poll(bool quitting, long frame);

    XrStereoSession* session() const { return xr_.get(); }
    bool running() const { return xr_ && xr_->running(); }
    /// Why the viewer is in desktop mode ("" while the headset runs).
    const std::string& fallbackReason() const { return fallback_; }
    /// The frame count when the viewer dropped to the desktop, -1 if it has not.
    long desktopSinceFrame() const { return desktop_since_frame_; }

  private:
    RunLog* log_;
    bool quiet_ = false;
    std::unique_ptr<XrStereoSession> xr_;
    std::string fallback_;
    long desktop_since_frame_ = -1;
    bool was_focused_ = false;
};

}  // namespace viewer
