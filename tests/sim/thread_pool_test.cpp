// tests/sim/thread_pool_test.cpp: sim's internal pool (sim/src/thread_pool.hpp).
#include "thread_pool.hpp"

#include <doctest/doctest.h>

#include <atomic>
#include <stdexcept>
#include <vector>

TEST_CASE("every task runs exactly once, on a valid worker, run after run") {
    for (int threads : {1, 2, 5}) {
        sim::ThreadPool pool(threads);
        CHECK(pool.size() == threads);
        for (std::size_t tasks : {0u, 1u, 7u, 1000u}) {
            std::vector<std::atomic<int>> ran(tasks);
            std::atomic<int> bad_worker{0};
            pool.run(tasks, [&](std::size_t task, int worker) {
                ran[task].fetch_add(1);
                bad_worker += worker < 0 || worker >= threads;
            });
            int wrong = 0;
            for (auto& r : ran) wrong += r.load() != 1;
            CHECK(wrong == 0);
            CHECK(bad_worker == 0);
        }
    }
}

TEST_CASE("an exception in a task reaches the caller and the pool stays usable") {
    sim::ThreadPool pool(3);
    CHECK_THROWS_WITH_AS(pool.run(100, [](std::size_t task, int) {
        if (task == 37) throw std::runtime_error("task 37 failed");
    }), "task 37 failed", std::runtime_error);
    std::atomic<int> count{0};
    pool.run(50, [&](std::size_t, int) { ++count; });
    CHECK(count == 50);
    CHECK(sim::resolveThreads(0) >= 1);
    CHECK(sim::resolveThreads(3) == 3);
}
