// engine/shuffle.hpp: the project's one shuffle. Policy: written here, not std::shuffle,
// because std::shuffle's permutation differs between standard libraries and seeded
// results (RANSAC's ground, the viewer's LOD order) must not depend on the one in use.
// It draws exactly as GCC's libstdc++ std::shuffle does with a 64-bit engine, so clouds
// made before it existed are reproduced bit for bit.
#pragma once
#include <cstdint>
#include <iterator>
#include <limits>
#include <utility>

namespace engine {

/// The high and low 64 bits of a * b, in portable integer arithmetic.
inline void multiply64(std::uint64_t a, std::uint64_t b, std::uint64_t& hi, std::uint64_t& lo) {
    const std::uint64_t a_lo = a & 0xFFFFFFFFu, a_hi = a >> 32, b_lo = b & 0xFFFFFFFFu, b_hi = b >> 32;
    const std::uint64_t p0 = a_lo * b_lo, p1 = a_lo * b_hi, p2 = a_hi * b_lo, p3 = a_hi * b_hi;
    const std::uint64_t mid = (p0 >> 32) + (p1 & 0xFFFFFFFFu) + (p2 & 0xFFFFFFFFu);
    lo = (mid << 32) | (p0 & 0xFFFFFFFFu);
    hi = p3 + (p1 >> 32) + (p2 >> 32) + (mid >> 32);
}

/// A uniform integer in [0, range), range > 0, from an engine giving all 64-bit values
/// (std::mt19937_64): Lemire's nearly divisionless method (multiply, reject the few
/// biased low products).
template <class Engine>
std::uint64_t uniformBelow(Engine& rng, std::uint64_t range) {
    static_assert(Engine::min() == 0 && Engine::max() == std::numeric_limits<std::uint64_t>::max(),
                  "engine::uniformBelow needs a full-range 64-bit engine such as std::mt19937_64");
    std::uint64_t hi = 0, lo = 0;
    multiply64(std::uint64_t(rng()), range, hi, lo);
    if (lo < range) {
        const std::uint64_t threshold = (0 - range) % range;
        while (lo < threshold) multiply64(std::uint64_t(rng()), range, hi, lo);
    }
    return hi;
}

/// Shuffles [first, last) uniformly with `rng` (Fisher-Yates). While n * n fits in 64
/// bits, one draw gives the swap positions of two elements (x / (k + 1), x % (k + 1) for
/// x below k * (k + 1)), after one single draw of 0 or 1 when n is even.
template <class RandomIt, class Engine>
void shuffle(RandomIt first, RandomIt last, Engine& rng) {
    using std::swap;
    if (first == last) return;
    const std::uint64_t n = std::uint64_t(last - first);
    if (std::numeric_limits<std::uint64_t>::max() / n >= n) {
        RandomIt i = first + 1;
        if (n % 2 == 0) {
            swap(*i, *(first + std::ptrdiff_t(uniformBelow(rng, 2))));
            ++i;
        }
        while (i != last) {
            const std::uint64_t k = std::uint64_t(i - first) + 1;  // positions [0, k) for *i
            const std::uint64_t x = uniformBelow(rng, k * (k + 1));
            swap(*i, *(first + std::ptrdiff_t(x / (k + 1))));
            ++i;
            swap(*i, *(first + std::ptrdiff_t(x % (k + 1))));
            ++i;
        }
        return;
    }
    for (RandomIt i = first + 1; i != last; ++i)
        swap(*i, *(first + std::ptrdiff_t(uniformBelow(rng, std::uint64_t(i - first) + 1))));
}

}  // namespace engine
