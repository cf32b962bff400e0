// viewer/src/stop_signal.hpp: SIGINT / SIGTERM as a request to stop, polled by the frame
// loop, so Ctrl-C or `timeout -s INT` finish the frame, write the logs and end the XR
// session instead of killing the process mid-write.
#pragma once
#include <csignal>

namespace viewer {

/// While alive, SIGINT and SIGTERM set a flag instead of ending the process (signals the
/// process ignores, as under nohup, stay ignored). The destructor restores the previous
/// handlers.
class StopSignal {
  public:
    StopSignal();
    ~StopSignal();
    StopSignal(const StopSignal&) = delete;
    StopSignal& operator=(const StopSignal&) = delete;
    /// The signal received, 0 if none.
    static int received();

  private:
    struct sigaction old_int_{}, old_term_{};
    bool int_installed_ = false, term_installed_ = false;
};

}  // namespace viewer
