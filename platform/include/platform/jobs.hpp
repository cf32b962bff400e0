// platform/jobs.hpp: runs independent pieces of work a fixed number at a time, so commands
// that offer `--jobs K` share one way to start, join and report their workers.
#pragma once
#include <cstddef>
#include <functional>

namespace platform {

// Runs fn(i) for every i in [0, n), at most `jobs` at once (1 runs them in order on the
// calling thread). After the first exception no new piece starts; the pieces already
// running finish, and that first exception is rethrown once all workers have joined.
void runJobs(std::size_t n, int jobs, const std::function<void(std::size_t)>& fn);

}  // namespace platform
