// sim/src/parallel.hpp: the generator's workers, a oneTBB task_arena of `threads` slots.
#pragma once
#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/global_control.h>
#include <oneapi/tbb/info.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/partitioner.h>
#include <oneapi/tbb/task_arena.h>

#include <algorithm>
#include <cstddef>
#include <memory>

namespace sim {

/// Number of threads for a request: 0 = every core oneTBB sees (at least 1).
inline int resolveThreads(int requested) {
    if (requested > 0) return requested;
    return std::max(1, tbb::info::default_concurrency());
}

/// `threads` concurrent workers (the calling thread takes one slot). oneTBB keeps one
/// worker per core by default; a larger request raises that limit while this object lives,
/// so `--threads N` means N threads as it says.
class Workers {
  public:
    explicit Workers(int threads) : arena_(std::max(1, threads)) {
        if (threads > tbb::info::default_concurrency())
            allow_ = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                           std::size_t(threads));
    }
    int size() const { return arena_.max_concurrency(); }

    /// Calls fn(task) once for every task in [0, tasks), in any order and on any worker,
    /// and returns when all are done; an exception thrown by fn reaches the caller (the
    /// tasks not started yet are skipped). Results must go to per-task slots.
    template <class Fn>
    void run(std::size_t tasks, const Fn& fn) {
        if (tasks == 0) return;
        arena_.execute([&] {
            tbb::parallel_for(
                tbb::blocked_range<std::size_t>(0, tasks, 1),
                [&](const tbb::blocked_range<std::size_t>& r) {
                    for (std::size_t t = r.begin(); t != r.end(); ++t) fn(t);
                },
                tbb::simple_partitioner());
        });
    }

  private:
    std::unique_ptr<tbb::global_control> allow_;  // before the arena: it outlives its use
    tbb::task_arena arena_;
};

}  // namespace sim
