// core/random.hpp: the project's seeded random numbers, written here so that a seed gives
// the same numbers with every compiler and standard library (results are compared byte
// for byte across machines). Three uses, each with its own reason:
// - SplitMix64 streams (Steele, Lea, Flood 2014): the corpus draws every sampled value
//   from one (corpus/random.hpp seeds them per item and key);
// - mix64 alone, as a counter-based generator: the sensor models hash (seed, stream,
//   view, pixel, draw) into one word, so a number never depends on the thread or the
//   order pixels are traced in (sim/src/sensor_noise.cpp); unitOpen makes it a uniform;
// - shuffle over std::mt19937_64 (RANSAC's ground, the viewer's LOD order): not
//   std::shuffle, whose permutation differs between standard libraries. It draws exactly
//   as GCC's libstdc++ std::shuffle does with a 64-bit engine, so clouds made before it
//   existed are reproduced bit for bit.
// All of it is integer arithmetic (and one IEEE multiply per uniform double).
#pragma once
#include <algorithm>
#include <cstdint>
#include <iterator>
#include <limits>
#include <utility>

namespace core {

/// The SplitMix64 finaliser of x: a bijection of 64-bit words with full avalanche.
constexpr std::uint64_t mix64(std::uint64_t x) {
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
    return x ^ (x >> 31);
}

/// 2^64 / golden ratio, SplitMix64's increment (odd: every step reaches a new state).
inline constexpr std::uint64_t kGolden = 0x9e3779b97f4a7c15ull;

/// Uniform in [0, 1): the top 53 bits of `bits` times 2^-53.
constexpr double unitHalfOpen(std::uint64_t bits) { return double(bits >> 11) * 0x1.0p-53; }
/// Uniform in (0, 1), never 0 (for a logarithm): the top 53 bits, plus one half, times 2^-53.
/// From 2^52 on, k + 0.5 rounds to an even neighbour; the top word alone would round to
/// 2^53 and give 1, so it gives the largest double below 1 instead.
constexpr double unitOpen(std::uint64_t bits) {
    return std::min((double(bits >> 11) + 0.5) * 0x1.0p-53, 0x1.fffffffffffffp-1);
}

/// The high and low 64 bits of a * b, in portable integer arithmetic.
constexpr void multiply64(std::uint64_t a, std::uint64_t b, std::uint64_t& hi, std::uint64_t& lo) {
    const std::uint64_t a_lo = a & 0xFFFFFFFFu, a_hi = a >> 32, b_lo = b & 0xFFFFFFFFu, b_hi = b >> 32;
    const std::uint64_t p0 = a_lo * b_lo, p1 = a_lo * b_hi, p2 = a_hi * b_lo, p3 = a_hi * b_hi;
    const std::uint64_t mid = (p0 >> 32) + (p1 & 0xFFFFFFFFu) + (p2 & 0xFFFFFFFFu);
    lo = (mid << 32) | (p0 & 0xFFFFFFFFu);
    hi = p3 + (p1 >> 32) + (p2 >> 32) + (mid >> 32);
}

/// SplitMix64: a 64-bit state advanced by kGolden, then mixed by mix64.
class SplitMix64 {
  public:
    explicit constexpr SplitMix64(std::uint64_t seed) : state_(seed) {}
    constexpr std::uint64_t next() {
        state_ += kGolden;
        return mix64(state_);
    }
    /// Uniform in [0, 1) (unitHalfOpen of next()).
    constexpr double unit() { return unitHalfOpen(next()); }
    /// Uniform in [lo, hi] (lo + (hi - lo) * unit(); hi itself only when lo == hi).
    constexpr double uniform(double lo, double hi) {
        const double u = unit();
        return lo == hi ? lo : lo + (hi - lo) * u;
    }
    /// Uniform integer in [0, n), n >= 1: the high word of next() * n, without
    /// rejection (bias below 2^-40 for n < 2^24; uniformBelow rejects for exactness).
    constexpr std::uint64_t below(std::uint64_t n);

  private:
    std::uint64_t state_;
};

/// A uniform integer in [0, range), range > 0, from an engine giving all 64-bit values
/// (std::mt19937_64): Lemire's nearly divisionless method (multiply, reject the few
/// biased low products).
template <class Engine>
std::uint64_t uniformBelow(Engine& rng, std::uint64_t range) {
    static_assert(Engine::min() == 0 && Engine::max() == std::numeric_limits<std::uint64_t>::max(),
                  "core::uniformBelow needs a full-range 64-bit engine such as std::mt19937_64");
    std::uint64_t hi = 0, lo = 0;
    multiply64(std::uint64_t(rng()), range, hi, lo);
    if (lo < range) {
        const std::uint64_t threshold = (0 - range) % range;
        while (lo < threshold) multiply64(std::uint64_t(rng()), range, hi, lo);
    }
    return hi;
}

constexpr std::uint64_t SplitMix64::below(std::uint64_t n) {
    std::uint64_t hi = 0, lo = 0;
    multiply64(next(), n, hi, lo);
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

}  // namespace core
