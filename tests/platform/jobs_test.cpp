// tests/platform/jobs_test.cpp: every piece runs once, in order with one job, and the first
// error stops new pieces and is rethrown after the workers join.
#include <doctest/doctest.h>
#include <platform/jobs.hpp>

#include <algorithm>
#include <atomic>
#include <mutex>
#include <stdexcept>
#include <vector>

TEST_CASE("runJobs runs every piece once, in order with one job") {
    std::vector<std::size_t> order;
    platform::runJobs(5, 1, [&](std::size_t i) { order.push_back(i); });
    CHECK(order == std::vector<std::size_t>{0, 1, 2, 3, 4});

    std::vector<std::atomic<int>> runs(100);
    platform::runJobs(runs.size(), 3, [&](std::size_t i) { ++runs[i]; });
    for (const auto& r : runs) CHECK(r.load() == 1);
    platform::runJobs(0, 4, [&](std::size_t) { FAIL("no piece to run"); });
}

TEST_CASE("runJobs rethrows the first error and starts no new piece after it") {
    std::vector<std::size_t> ran;
    std::mutex mutex;
    const auto piece = [&](std::size_t i) {
        {
            const std::lock_guard lock(mutex);
            ran.push_back(i);
        }
        if (i == 2) throw std::runtime_error("piece 2 failed");
    };
    CHECK_THROWS_WITH(platform::runJobs(10, 1, piece), "piece 2 failed");
    CHECK(ran == std::vector<std::size_t>{0, 1, 2});
    ran.clear();
    // With several workers the error is rethrown after the join, and no piece runs twice.
    // How many pieces the other worker takes before the error is seen depends on how the
    // threads are scheduled (on a loaded machine it may take them all), so that is not
    // counted here; one worker shows that no piece starts after the error.
    CHECK_THROWS_WITH(platform::runJobs(1000, 2, piece), "piece 2 failed");
    std::vector<std::size_t> sorted = ran;
    std::sort(sorted.begin(), sorted.end());
    CHECK(std::adjacent_find(sorted.begin(), sorted.end()) == sorted.end());
    CHECK(std::find(ran.begin(), ran.end(), std::size_t{2}) != ran.end());
}
