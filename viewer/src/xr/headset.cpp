// viewer/src/xr/headset.cpp: starting, polling and dropping the OpenXR session.
#include "xr/headset.hpp"

#include <core/error.hpp>

#include <cstdio>

namespace viewer {

void Headset::start(GLFWwindow* window, bool use_xr) {
    if (use_xr) {
        std::string reason;
        try {
            xr_ = XrStereoSession::create(window, *log_, reason);
        } catch (const core::Error& e) {
            reason = e.what();
        }
        if (!xr_) fallBack(reason, 0);
    } else {
        fallBack("OpenXR disabled (--no-xr)", 0);
    }
    log_->set("xr_active_at_start", xr_ != nullptr);
}

void Headset::fallBack(const std::string& reason, long frame) {
    xr_.reset();
    fallback_ = reason;
    desktop_since_frame_ = frame;
    log_->event("desktop mode: " + reason);
    if (!quiet_) std::fprintf(stderr, "ladarvr: view: %s; desktop mode (mouse and keyboard camera)\n", reason.c_str());
}

bool Headset::poll(bool quitting, long frame) {
    if (!xr_) return true;
    const XrPoll poll = xr_->pollEvents();
    if (poll == XrPoll::Ok && xr_->focused() != was_focused_) {
        was_focused_ = xr_->focused();
        if (!quiet_)
            std::fprintf(stderr, "ladarvr: view: OpenXR session %s\n", was_focused_ ? "focused" : "not focused");
    }
    if (poll == XrPoll::Exit) {
        log_->event("xr: session exited");
        xr_.reset();
        if (quitting) return false;
        fallBack("the OpenXR session ended", frame);
    } else if (poll == XrPoll::Lost) {
        fallBack("the OpenXR runtime was lost", frame);
        if (quitting) return false;
    }
    return true;
}

}  // namespace viewer
