// corpus/random.hpp: the random numbers behind every sampled value. Item i of a SPEC with
// seed s draws each key from its own SplitMix64 stream (core/random.hpp) seeded by a hash
// of (s, i, key), so an item depends on nothing else: not on other items, the order they
// are built in, the thread count or which other keys vary. Only integer arithmetic and
// one IEEE multiply-add per value, so the values are the same bit for bit on any machine.
#pragma once
#include <core/random.hpp>

#include <cstdint>
#include <string_view>

namespace corpus {

using core::mix64;
using core::SplitMix64;

/// The seed of item `index` (0-based) of a SPEC with `seed`; recorded in the manifest.
std::uint64_t itemSeed(std::uint64_t seed, std::uint64_t index);

/// The stream of `key` for the item whose seed is `item_seed` (FNV-1a of the key, mixed).
SplitMix64 keyStream(std::uint64_t item_seed, std::string_view key);

}  // namespace corpus
