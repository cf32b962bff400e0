// corpus: SplitMix64 streams per (seed, item, key).
#include <corpus/random.hpp>

namespace corpus {

std::uint64_t itemSeed(std::uint64_t seed, std::uint64_t index) {
    return mix64(mix64(seed ^ 0x6c61646172767221ull) + index * core::kGolden + 1);
}

SplitMix64 keyStream(std::uint64_t item_seed, std::string_view key) {
    std::uint64_t h = 0xcbf29ce484222325ull;  // FNV-1a, 64 bits
    for (const char c : key) {
        h ^= std::uint8_t(c);
        h *= 0x100000001b3ull;
    }
    return SplitMix64(mix64(item_seed ^ mix64(h)));
}

}  // namespace corpus
