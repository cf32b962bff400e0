// sim/src/thread_pool.cpp
#include "thread_pool.hpp"

#include <algorithm>

namespace sim {

int resolveThreads(int requested) {
    if (requested > 0) return requested;
    return std::max(1, int(std::thread::hardware_concurrency()));
}

ThreadPool::ThreadPool(int threads) {
    for (int w = 1; w < std::max(1, threads); ++w) workers_.emplace_back([this, w] { workerLoop(w); });
}

ThreadPool::~ThreadPool() {
    {
        std::lock_guard lock(mutex_);
        stop_ = true;
    }
    wake_.notify_all();
    for (auto& t : workers_) t.join();
}

void ThreadPool::drain(int worker) {
    std::unique_lock lock(mutex_);
    while (next_ < tasks_) {
        const std::size_t task = next_++;
        ++in_flight_;
        lock.unlock();
        std::exception_ptr error;
        try {
            (*fn_)(task, worker);
        } catch (...) {
            error = std::current_exception();
        }
        lock.lock();
        --in_flight_;
        if (error) {
            if (!error_) error_ = error;
            next_ = tasks_;  // abandon the tasks not handed out yet
        }
        if (in_flight_ == 0 && next_ >= tasks_) done_.notify_all();
    }
}

void ThreadPool::workerLoop(int worker) {
    std::size_t seen = 0;
    std::unique_lock lock(mutex_);
    for (;;) {
        wake_.wait(lock, [&] { return stop_ || generation_ != seen; });
        if (stop_) return;
        seen = generation_;
        lock.unlock();
        drain(worker);
        lock.lock();
    }
}

void ThreadPool::run(std::size_t tasks, const std::function<void(std::size_t, int)>& fn) {
    {
        std::lock_guard lock(mutex_);
        fn_ = &fn;
        tasks_ = tasks;
        next_ = 0;
        error_ = nullptr;
        ++generation_;
    }
    if (!workers_.empty()) wake_.notify_all();
    drain(0);
    std::unique_lock lock(mutex_);
    // Every task has been handed out and every one handed out has returned; a worker that
    // wakes late finds next_ == tasks_ and goes back to sleep.
    done_.wait(lock, [&] { return next_ >= tasks_ && in_flight_ == 0; });
    fn_ = nullptr;
    if (error_) std::rethrow_exception(error_);
}

}  // namespace sim
