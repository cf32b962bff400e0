// sim/src/sensor_noise.cpp: counter-based random numbers for every sensor model, and the
// range error. A number depends only on (seed, stream, view, pixel, draw), never on the
// thread or the order in which pixels are traced, so clouds are bit-identical whatever the
// thread count.
#include "sensor_models.hpp"

#include <cmath>
#include <numbers>

namespace sim::sensor_model {
namespace {

// SplitMix64's finaliser: a bijection of 64-bit words with good avalanche.
std::uint64_t mix(std::uint64_t z) {
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

constexpr std::uint64_t kGolden = 0x9E3779B97F4A7C15ull;

// A uniform number in (0, 1): 53 random bits, never 0 (the logarithm below needs that).
double uniform(std::uint64_t bits) { return (double(bits >> 11) + 0.5) * 0x1.0p-53; }

}  // namespace

std::uint64_t key(std::uint64_t seed, Stream stream, std::uint64_t a, std::uint64_t b) {
    std::uint64_t k = mix(seed + kGolden);
    k = mix(k ^ (std::uint64_t(stream) * kGolden));
    k = mix(k ^ (a + kGolden));
    return mix(k ^ (b * kGolden + 1));
}

double gaussian(std::uint64_t k, std::uint64_t n) {
    // Box-Muller on two uniforms; draw n uses the cosine (even n) or sine (odd n) of pair n/2.
    const std::uint64_t pair = mix(k + (n / 2 + 1) * kGolden);
    const double u1 = uniform(pair), u2 = uniform(mix(pair ^ kGolden));
    const double r = std::sqrt(-2.0 * std::log(u1));
    const double angle = 2.0 * std::numbers::pi * u2;
    return n % 2 == 0 ? r * std::cos(angle) : r * std::sin(angle);
}

double rangeError_m(const SensorOptions& o, std::uint64_t seed, int view, std::uint64_t pixel, int ret) {
    if (o.range_noise_m <= 0.0) return 0.0;
    return o.range_noise_m * gaussian(key(seed, Stream::Range, std::uint64_t(view), pixel), std::uint64_t(ret));
}

}  // namespace sim::sensor_model
