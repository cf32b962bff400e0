// sim/src/sensor_noise.cpp: counter-based random numbers for every sensor model, and the
// range error. A number depends only on (seed, stream, view, pixel, draw), never on the
// thread or the order in which pixels are traced, so clouds are bit-identical whatever the
// thread count.
#include "sensor_models.hpp"

#include <core/random.hpp>

#include <cmath>
#include <numbers>

namespace sim::sensor_model {

using core::kGolden;
using core::mix64;

std::uint64_t key(std::uint64_t seed, Stream stream, std::uint64_t a, std::uint64_t b) {
    std::uint64_t k = mix64(seed + kGolden);
    k = mix64(k ^ (std::uint64_t(stream) * kGolden));
    k = mix64(k ^ (a + kGolden));
    return mix64(k ^ (b * kGolden + 1));
}

double gaussian(std::uint64_t k, std::uint64_t n) {
    // Box-Muller on two uniforms; draw n uses the cosine (even n) or sine (odd n) of pair n/2.
    const std::uint64_t pair = mix64(k + (n / 2 + 1) * kGolden);
    const double u1 = core::unitOpen(pair), u2 = core::unitOpen(mix64(pair ^ kGolden));
    const double r = std::sqrt(-2.0 * std::log(u1));
    const double angle = 2.0 * std::numbers::pi * u2;
    return n % 2 == 0 ? r * std::cos(angle) : r * std::sin(angle);
}

double rangeError_m(const SensorOptions& o, std::uint64_t seed, int view, std::uint64_t pixel, int ret) {
    if (o.range_noise_m <= 0.0) return 0.0;
    return o.range_noise_m * gaussian(key(seed, Stream::Range, std::uint64_t(view), pixel), std::uint64_t(ret));
}

}  // namespace sim::sensor_model
