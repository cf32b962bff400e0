// platform/src/jobs.cpp: a shared index handed out to `jobs` workers; the first error wins.
#include "platform/jobs.hpp"

#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace platform {

void runJobs(std::size_t n, int jobs, const std::function<void(std::size_t)>& fn) {
    std::atomic<std::size_t> next{0};
    std::mutex mutex;
    std::exception_ptr error;
    const auto worker = [&] {
        for (std::size_t i = next++; i < n; i = next++) {
            try {
                fn(i);
            } catch (...) {
                const std::lock_guard lock(mutex);
                if (!error) error = std::current_exception();
                next = n;
                return;
            }
        }
    };
    jobs = std::max(1, std::min<int>(jobs, int(std::min<std::size_t>(n, 1024))));
    if (jobs == 1) {
        worker();
    } else {
        std::vector<std::thread> threads;
        for (int j = 0; j < jobs; ++j) threads.emplace_back(worker);
        for (std::thread& th : threads) th.join();
    }
    if (error) std::rethrow_exception(error);
}

}  // namespace platform
