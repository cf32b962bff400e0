// tests/core/random_test.cpp: core/random.hpp: SplitMix64, the uniforms and the one seeded shuffle.
#include <core/random.hpp>

#include <doctest/doctest.h>

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <random>
#include <vector>

namespace {

std::vector<std::uint32_t> shuffled(std::size_t n, std::uint64_t seed) {
    std::vector<std::uint32_t> v(n);
    std::iota(v.begin(), v.end(), 0u);
    std::mt19937_64 rng(seed);
    core::shuffle(v.begin(), v.end(), rng);
    return v;
}

}  // namespace

TEST_CASE("shuffle: multiply64 gives the exact 128-bit product") {
    std::uint64_t hi = 0, lo = 0;
    core::multiply64(~0ull, ~0ull, hi, lo);  // (2^64 - 1)^2 = 2^128 - 2^65 + 1
    CHECK(hi == 0xFFFFFFFFFFFFFFFEull);
    CHECK(lo == 1);
    core::multiply64(0x123456789ABCDEF0ull, 0x10ull, hi, lo);
    CHECK(hi == 0x1);
    CHECK(lo == 0x23456789ABCDEF00ull);
    std::mt19937_64 rng(5);
    for (int i = 0; i < 1000; ++i) {
        const std::uint64_t a = rng(), b = rng();
        core::multiply64(a, b, hi, lo);
        CHECK(lo == a * b);  // the low half is ordinary wrapping multiplication
#ifdef __SIZEOF_INT128__
        CHECK(hi == std::uint64_t((unsigned __int128)a * b >> 64));
#endif
    }
}

TEST_CASE("shuffle: a permutation, a pure function of the seed, known answers pinned") {
    for (std::size_t n : {0u, 1u, 2u, 3u, 10u, 1001u}) {
        auto v = shuffled(n, 7);
        CHECK(v == shuffled(n, 7));
        std::sort(v.begin(), v.end());
        for (std::size_t i = 0; i < n; ++i) CHECK(v[i] == i);
    }
    CHECK(shuffled(1001, 7) != shuffled(1001, 8));
    // Pinned so that a change of the draws (which would change every RANSAC ground and
    // LOD order) shows up on every standard library, not only where std::shuffle agrees.
    CHECK(shuffled(10, 1) == std::vector<std::uint32_t>{6, 9, 4, 8, 1, 3, 2, 5, 0, 7});
}

TEST_CASE("shuffle: uniformBelow stays in range and is roughly uniform") {
    std::mt19937_64 rng(11);
    std::vector<int> hits(6, 0);
    for (int i = 0; i < 60000; ++i) {
        const std::uint64_t x = core::uniformBelow(rng, 6);
        REQUIRE(x < 6);
        ++hits[x];
    }
    for (int h : hits) CHECK(h > 9000);
    for (int h : hits) CHECK(h < 11000);
    CHECK(core::uniformBelow(rng, 1) == 0);
}

#ifdef __GLIBCXX__
TEST_CASE("shuffle: the same permutation as libstdc++'s std::shuffle (RANSAC's clouds stay the same)") {
    for (std::size_t n : {1u, 2u, 3u, 4u, 5u, 64u, 65u, 1000u, 12345u}) {
        for (std::uint64_t seed : {1ull, 2ull, 0xDEADBEEFull}) {
            std::vector<std::uint32_t> expected(n);
            std::iota(expected.begin(), expected.end(), 0u);
            std::mt19937_64 rng(seed);
            std::shuffle(expected.begin(), expected.end(), rng);
            CAPTURE(n);
            CAPTURE(seed);
            CHECK(shuffled(n, seed) == expected);
        }
    }
}
#endif

TEST_CASE("random: SplitMix64 gives the reference sequence, below is the high word of next() * n") {
    core::SplitMix64 r(0);
    CHECK(r.next() == 0xe220a8397b1dcdafull);  // the reference SplitMix64's first output for seed 0
    CHECK(r.next() == 0x6e789e6aa1b965f4ull);
    CHECK(core::mix64(0) == 0);  // the finaliser is a bijection fixing 0
    core::SplitMix64 a(12345), b(12345);
    for (std::uint64_t n : {1ull, 2ull, 3ull, 1000ull, 1ull << 40, ~0ull}) {
        const std::uint64_t x = a.next();
        const auto expect = std::uint64_t((static_cast<unsigned __int128>(x) * n) >> 64);
        const std::uint64_t got = b.below(n);
        CHECK(got == expect);
        CHECK(got < n);
    }
}

TEST_CASE("random: the uniforms take the top 53 bits, unitOpen never reaches 0 or 1") {
    CHECK(core::unitHalfOpen(0) == 0.0);
    CHECK(core::unitHalfOpen(~0ull) == 1.0 - 0x1.0p-53);
    CHECK(core::unitOpen(0) == 0x1.0p-54);
    CHECK(core::unitOpen(~0ull) < 1.0);
    core::SplitMix64 r(7);
    CHECK(r.uniform(2.5, 2.5) == 2.5);
    for (int i = 0; i < 1000; ++i) {
        const double u = r.uniform(-1.0, 3.0);
        CHECK(u >= -1.0);
        CHECK(u < 3.0);
    }
}
