// bench/src/plain_loop.cpp: see plain_loop.hpp.
#include "plain_loop.hpp"

#include "common.hpp"

#include <algorithm>
#include <atomic>
#include <span>
#include <thread>

namespace bench {
namespace {

// Runs work() on `threads` threads (this one included) and returns the wall time, s.
template <class Work>
double timedOnThreads(int threads, const Work& work) {
    const Clock::time_point t0 = Clock::now();
    std::vector<std::thread> pool;
    for (int t = 1; t < threads; ++t) pool.emplace_back(work);
    work();
    for (auto& t : pool) t.join();
    return secondsSince(t0);
}

}  // namespace

double plainLoopSeconds(const sim::RayCaster& caster, const std::vector<sim::Ray>& rays, std::vector<sim::Hit>& hits,
                        int threads) {
    hits.resize(rays.size());
    constexpr std::size_t kChunk = 4096;
    std::atomic<std::size_t> next{0};
    const auto work = [&] {
        for (;;) {
            const std::size_t begin = next.fetch_add(kChunk);
            if (begin >= rays.size()) return;
            const std::size_t n = std::min(kChunk, rays.size() - begin);
            caster.intersect(std::span(rays).subspan(begin, n), std::span(hits).subspan(begin, n));
        }
    };
    return timedOnThreads(threads, work);
}

double plainPacketLoopSeconds(const sim::RayCaster& caster, const std::vector<sim::Ray>& rays,
                              std::vector<sim::Hit>& hits, int threads, std::size_t row_px) {
    hits.resize(rays.size());
    row_px = std::max<std::size_t>(1, row_px);
    const std::size_t chunk = std::max<std::size_t>(1, 4096 / row_px) * row_px;
    std::atomic<std::size_t> next{0};
    const auto work = [&] {
        for (;;) {
            const std::size_t begin = next.fetch_add(chunk);
            if (begin >= rays.size()) return;
            const std::size_t end = std::min(rays.size(), begin + chunk);
            for (std::size_t row = begin; row < end; row += row_px) {
                const std::size_t n = std::min(row_px, end - row);
                caster.intersect16(std::span(rays).subspan(row, n), std::span(hits).subspan(row, n));
            }
        }
    };
    return timedOnThreads(threads, work);
}

}  // namespace bench
