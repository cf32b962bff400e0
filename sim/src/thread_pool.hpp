// sim/src/thread_pool.hpp: a fixed pool of worker threads running index ranges.
#pragma once
#include <condition_variable>
#include <cstddef>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace sim {

/// `threads` workers (the calling thread is one of them). run(n, fn) calls fn(task, worker)
/// for task in [0, n) with tasks handed out dynamically, and returns when all are done;
/// the first exception thrown by fn is rethrown. Results must go to per-task slots so that
/// they do not depend on which worker ran a task.
class ThreadPool {
public:
    explicit ThreadPool(int threads);
    ~ThreadPool();
    ThreadPool(const ThreadPool&) = delete;
    ThreadPool& operator=(const ThreadPool&) = delete;

    int size() const { return int(workers_.size()) + 1; }
    void run(std::size_t tasks, const std::function<void(std::size_t task, int worker)>& fn);

private:
    void workerLoop(int worker);
    void drain(int worker);

    std::vector<std::thread> workers_;
    std::mutex mutex_;
    std::condition_variable wake_, done_;
    const std::function<void(std::size_t, int)>* fn_ = nullptr;
    std::size_t tasks_ = 0, next_ = 0, in_flight_ = 0;
    std::size_t generation_ = 0;
    bool stop_ = false;
    std::exception_ptr error_;
};

/// Number of threads for a request: 0 = std::thread::hardware_concurrency() (at least 1).
int resolveThreads(int requested);

}  // namespace sim
