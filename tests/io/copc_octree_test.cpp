// Tests for io/src/copc/copc_octree.hpp's ordered work: every item worked once, emitted
// in order on the caller's thread, never more than the window (in items, or in weight)
// begun and not emitted, and the first error rethrown with nothing begun after it.
#include "../../io/src/copc/copc_octree.hpp"

#include <doctest/doctest.h>

#include <atomic>
#include <mutex>
#include <stdexcept>
#include <thread>
#include <vector>

TEST_CASE("copc_octree: ordered work emits every item once, in order, within its window") {
    for (const int threads : {0, 1, 3}) {
        for (const std::size_t window : {1u, 2u, 5u}) {
            CAPTURE(threads);
            CAPTURE(window);
            constexpr std::size_t n = 200;
            std::vector<std::atomic<int>> worked(n);
            std::atomic<int> open{0}, most_open{0};
            std::vector<std::size_t> emitted;
            const std::thread::id caller = std::this_thread::get_id();
            bool emitted_elsewhere = false;
            io::detail::orderedParallel(
                n, threads, window,
                [&](std::size_t i) {
                    const int now = ++open;
                    for (int seen = most_open.load(); now > seen && !most_open.compare_exchange_weak(seen, now);) {}
                    // Uneven work, so that later items often finish first.
                    volatile std::size_t spin = 0;
                    for (std::size_t k = 0; k < (i % 7) * 20000; ++k) spin = spin + k;
                    ++worked[i];
                },
                [&](std::size_t i) {
                    if (std::this_thread::get_id() != caller) emitted_elsewhere = true;
                    CHECK(worked[i].load() == 1);
                    --open;
                    emitted.push_back(i);
                });
            REQUIRE(emitted.size() == n);
            for (std::size_t i = 0; i < n; ++i) CHECK(emitted[i] == i);
            for (std::size_t i = 0; i < n; ++i) CHECK(worked[i].load() == 1);
            CHECK(std::size_t(most_open.load()) <= window);
            CHECK_FALSE(emitted_elsewhere);
        }
    }
}

TEST_CASE("copc_octree: weighted ordered work holds at most the window's weight, or one item alone") {
    // Items weigh 2 to 18 while they run and half that once worked, and one item is heavier
    // than the window: the weight begun and not emitted never passes the window, except
    // by an item that begins alone.
    for (const int threads : {0, 1, 3}) {
        CAPTURE(threads);
        constexpr std::size_t n = 150, window = 24, heavy = 40;
        const auto weight = [](std::size_t i, bool worked) {
            const std::size_t w = i == heavy ? window + 5 : 2 * (1 + i % 9);
            return worked ? w / 2 : w;
        };
        std::mutex m;
        std::size_t held = 0, items = 0;
        bool over = false;
        std::vector<std::size_t> emitted;
        io::detail::orderedParallel(
            n, threads, window,
            [&](std::size_t i) {
                {
                    std::lock_guard<std::mutex> lock(m);
                    held += weight(i, false);
                    ++items;
                    if (held > window && items > 1) over = true;
                }
                volatile std::size_t spin = 0;
                for (std::size_t k = 0; k < (i % 5) * 20000; ++k) spin = spin + k;
                std::lock_guard<std::mutex> lock(m);
                held -= weight(i, false) - weight(i, true);
            },
            [&](std::size_t i) {
                std::lock_guard<std::mutex> lock(m);
                held -= weight(i, true);
                --items;
                emitted.push_back(i);
            },
            weight);
        REQUIRE(emitted.size() == n);
        for (std::size_t i = 0; i < n; ++i) CHECK(emitted[i] == i);
        CHECK_FALSE(over);
    }
}

TEST_CASE("copc_octree: ordered work stops at the first error and rethrows it") {
    for (const int threads : {0, 2}) {
        CAPTURE(threads);
        constexpr std::size_t n = 100, window = 4, bad = 10;
        std::mutex m;
        std::vector<std::size_t> begun, emitted;
        const auto work = [&](std::size_t i) {
            {
                std::lock_guard<std::mutex> lock(m);
                begun.push_back(i);
            }
            if (i == bad) throw std::runtime_error("item 10 failed");
        };
        std::string error;
        try {
            io::detail::orderedParallel(n, threads, window, work, [&](std::size_t i) { emitted.push_back(i); });
        } catch (const std::runtime_error& e) {
            error = e.what();
        }
        CHECK(error == "item 10 failed");
        for (std::size_t i : emitted) CHECK(i < bad);
        // Nothing begins past the window around the failed item.
        for (std::size_t i : begun) CHECK(i < bad + window);
        // An error in emit stops the run as well.
        error.clear();
        std::vector<std::size_t> emitted2;
        try {
            io::detail::orderedParallel(
                n, threads, window, [](std::size_t) {},
                [&](std::size_t i) {
                    if (i == 3) throw std::runtime_error("emit 3 failed");
                    emitted2.push_back(i);
                });
        } catch (const std::runtime_error& e) {
            error = e.what();
        }
        CHECK(error == "emit 3 failed");
        CHECK(emitted2 == std::vector<std::size_t>{0, 1, 2});
    }
}
