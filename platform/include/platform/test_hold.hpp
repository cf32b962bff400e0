// platform/test_hold.hpp: holding a run at a named point so that a test can act on it
// there (send a signal, look at its files) when the point is reached, not after a sleep.
// A hook is off unless its environment variable is set; it costs one getenv otherwise.
#pragma once
#include <string>
#include <string_view>

namespace platform {

/// Tells the FIFO `fifo` `line` (the call waits until the test opens it for reading),
/// then waits until something opens the FIFO for writing and closes it. A signal ends
/// the wait as it ends the run. Throws Error("<hook>: '<fifo>' is not a FIFO; allowed
/// <allowed> (a test hook)") when `fifo` is not one.
void holdOnFifo(const std::string& fifo, const std::string& line, std::string_view hook, std::string_view allowed);

/// The hook that holds every TempFile::commit() with the temporary written and closed,
/// not yet renamed into place: LADARVR_TEST_HOLD_COMMIT names a FIFO, which is told
/// "held <temporary's name>".
inline constexpr const char* kHoldCommitVariable = "LADARVR_TEST_HOLD_COMMIT";

}  // namespace platform
