// platform/cleanup.hpp: what this process made is removed when it is stopped.
//
// Every temporary file or folder the project creates (platform::TempFile, scratch files,
// report folders) is registered here while it exists. The first registration installs
// handlers for SIGINT, SIGTERM and SIGHUP (unless the signal is ignored, as under nohup):
// the handler removes the registered temporaries with unlinkat(2) only (async-signal-safe),
// then re-raises the signal with its default action, so the shell sees 130 (SIGINT), 143
// (SIGTERM) or 129 (SIGHUP) and the parent knows the run was stopped by a signal. A
// SIGKILL cannot be caught: what it leaves is a hidden ".ladarvr-tmp-<pid>-XXXXXX" that
// no reader mistakes for output and that the next run in that folder removes
// (platform/safe_file.hpp, removeStaleTemporaries).
#pragma once
#include <condition_variable>
#include <mutex>
#include <string>
#include <thread>

namespace platform {

/// Removes every registered temporary now (files first, then folders). Async-signal-safe:
/// only atomics and unlinkat(2). Called by the signal handlers, at exit and by Watchdog.
void removeTemporariesNow() noexcept;

/// Ends the process if it is still running `seconds` after construction: prints
/// "ladarvr: error: <message>" on stderr, removes the temporaries and exits with
/// `exit_code` (without unwinding: the thread that is late may be stuck anywhere).
/// Destroying the Watchdog first cancels it. seconds <= 0 or > 1e9 means never.
class Watchdog {
  public:
    Watchdog(double seconds, std::string message, int exit_code = 1);
    ~Watchdog();
    Watchdog(const Watchdog&) = delete;
    Watchdog& operator=(const Watchdog&) = delete;

  private:
    std::mutex mutex_;
    std::condition_variable wake_;
    bool cancelled_ = false;
    std::thread thread_;
};

namespace detail {

/// Registers `name` inside the directory open as `dirfd` (which must stay open until
/// unregistered) for removal on a signal; `is_dir` removes it with AT_REMOVEDIR (which
/// only succeeds once it is empty). Returns a slot for unregisterTemporary, -1 when the
/// table is full (the temporary is then only removed by its owner or the next run).
int registerTemporary(int dirfd, const char* name, bool is_dir) noexcept;
/// Forgets a slot (after the temporary was renamed into place or removed); -1 is ignored.
void unregisterTemporary(int slot) noexcept;

}  // namespace detail

}  // namespace platform
