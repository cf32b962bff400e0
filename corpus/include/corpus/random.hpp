// corpus/random.hpp: the random numbers behind every sampled value. Item i of a SPEC with
// seed s draws each key from its own SplitMix64 stream seeded by a hash of (s, i, key), so
// an item depends on nothing else: not on other items, the order they are built in, the
// thread count or which other keys vary. Only integer arithmetic and one IEEE multiply-add
// per value, so the values are the same bit for bit on any machine.
#pragma once
#include <cstdint>
#include <string_view>

namespace corpus {

/// SplitMix64 (Steele, Lea, Flood 2014): a 64-bit state advanced by a constant, then mixed.
class SplitMix64 {
public:
    explicit SplitMix64(std::uint64_t seed) : state_(seed) {}
    std::uint64_t next();
    /// Uniform in [0, 1): the top 53 bits of next() times 2^-53.
    double unit();
    /// Uniform in [lo, hi] (lo + (hi - lo) * unit(); hi itself only when lo == hi).
    double uniform(double lo, double hi);
    /// Uniform integer in [0, n), n >= 1 (multiply-high; bias below 2^-40 for n < 2^24).
    std::uint64_t below(std::uint64_t n);

private:
    std::uint64_t state_;
};

/// The SplitMix64 finaliser of x: a 64-bit mix with full avalanche.
std::uint64_t mix64(std::uint64_t x);

/// The seed of item `index` (0-based) of a SPEC with `seed`; recorded in the manifest.
std::uint64_t itemSeed(std::uint64_t seed, std::uint64_t index);

/// The stream of `key` for the item whose seed is `item_seed` (FNV-1a of the key, mixed).
SplitMix64 keyStream(std::uint64_t item_seed, std::string_view key);

}  // namespace corpus
