// bench/src/plain_loop.cpp: see plain_loop.hpp.
#include "plain_loop.hpp"

#include "common.hpp"

#include <algorithm>
#include <atomic>
#include <span>
#include <thread>

namespace bench {

double plainLoopSeconds(const sim::RayCaster& caster, const std::vector<sim::Ray>& rays,
                        std::vector<sim::Hit>& hits, int threads) {
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
    const Clock::time_point t0 = Clock::now();
    std::vector<std::thread> pool;
    for (int t = 1; t < threads; ++t) pool.emplace_back(work);
    work();
    for (auto& t : pool) t.join();
    return secondsSince(t0);
}

}  // namespace bench
