// corpus: SplitMix64 streams per (seed, item, key).
#include <corpus/random.hpp>

namespace corpus {

std::uint64_t mix64(std::uint64_t x) {
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
    return x ^ (x >> 31);
}

std::uint64_t SplitMix64::next() {
    state_ += 0x9e3779b97f4a7c15ull;
    return mix64(state_);
}

double SplitMix64::unit() { return double(next() >> 11) * 0x1.0p-53; }

double SplitMix64::uniform(double lo, double hi) {
    const double u = unit();
    return lo == hi ? lo : lo + (hi - lo) * u;
}

std::uint64_t SplitMix64::below(std::uint64_t n) {
    const unsigned __int128 product = (unsigned __int128)next() * n;
    return std::uint64_t(product >> 64);
}

std::uint64_t itemSeed(std::uint64_t seed, std::uint64_t index) {
    return mix64(mix64(seed ^ 0x6c61646172767221ull) + index * 0x9e3779b97f4a7c15ull + 1);
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
