// tests/sim/parallel_test.cpp: sim's workers (sim/src/parallel.hpp), a oneTBB task_arena.
#include "parallel.hpp"

#include <doctest/doctest.h>

#include <oneapi/tbb/task_arena.h>

#include <atomic>
#include <chrono>
#include <mutex>
#include <set>
#include <stdexcept>
#include <thread>
#include <vector>

TEST_CASE("every task runs exactly once, run after run, inside an arena of the requested size") {
    for (int threads : {1, 2, 5}) {
        sim::Workers workers(threads);
        CHECK(workers.size() == threads);
        for (std::size_t tasks : {0u, 1u, 7u, 1000u}) {
            std::vector<std::atomic<int>> ran(tasks);
            std::atomic<int> wrong_arena{0};
            workers.run(tasks, [&](std::size_t task) {
                ran[task].fetch_add(1);
                wrong_arena += tbb::this_task_arena::max_concurrency() != threads;
            });
            int wrong = 0;
            for (auto& r : ran) wrong += r.load() != 1;
            CHECK(wrong == 0);
            CHECK(wrong_arena == 0);
        }
    }
}

TEST_CASE("more threads than cores are honoured: every one of them takes part") {
    const int threads = int(std::thread::hardware_concurrency()) + 3;
    sim::Workers workers(threads);
    REQUIRE(workers.size() == threads);
    // Each task waits until `threads` distinct threads have arrived (or gives up after 5 s),
    // which only happens if the arena really runs that many at once.
    std::mutex m;
    std::set<std::thread::id> seen;
    std::atomic<int> arrived{0};
    workers.run(std::size_t(threads), [&](std::size_t) {
        {
            std::lock_guard lock(m);
            seen.insert(std::this_thread::get_id());
        }
        ++arrived;
        const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(5);
        while (arrived.load() < threads && std::chrono::steady_clock::now() < until) std::this_thread::yield();
    });
    CHECK(int(seen.size()) == threads);
}

TEST_CASE("an exception in a task reaches the caller and the workers stay usable") {
    sim::Workers workers(3);
    CHECK_THROWS_WITH_AS(workers.run(100,
                                     [](std::size_t task) {
                                         if (task == 37) throw std::runtime_error("task 37 failed");
                                     }),
                         "task 37 failed", std::runtime_error);
    std::atomic<int> count{0};
    workers.run(50, [&](std::size_t) { ++count; });
    CHECK(count == 50);
    CHECK(sim::resolveThreads(0) >= 1);
    CHECK(sim::resolveThreads(3) == 3);
}
