// sim/src/sensor_returns.cpp: the echoes of one pulse's sub-rays into discrete returns.
// A full-waveform receiver sees each surface in the footprint as a peak as wide as the
// pulse; two surfaces closer in range than the pulse's half length (c * tau / 2, 0.6 m for
// a 4 ns pulse) blur into one peak. Here the echoes are sorted by range and binned into
// that waveform's peaks directly: a new return starts where the gap to the previous echo
// is at least the range resolution. Each return is placed on its strongest echo's own
// sub-ray hit (not on the beam's axis), so target edges stay sharp.
#include "sensor_models.hpp"

#include <algorithm>

namespace sim::sensor_model {

std::size_t formReturns(std::span<Echo> echoes, double resolution_m, double min_power, ReturnMode mode,
                        int max_returns, std::span<Return> out, int* detected, int* first_rank) {
    *detected = 0;
    *first_rank = 1;
    if (echoes.empty()) return 0;
    std::sort(echoes.begin(), echoes.end(),
              [](const Echo& a, const Echo& b) { return a.t < b.t || (a.t == b.t && a.sub < b.sub); });
    // All returns of the pulse (a footprint has at most a few dozen sub-rays).
    constexpr std::size_t kMaxGroups = 64;
    Return groups[kMaxGroups];
    std::size_t n = 0;
    std::size_t begin = 0;
    for (std::size_t i = 1; i <= echoes.size(); ++i) {
        if (i < echoes.size() && double(echoes[i].t) - double(echoes[i - 1].t) < resolution_m) continue;
        Return r;
        r.strongest = std::uint32_t(begin);
        for (std::size_t j = begin; j < i; ++j) {
            r.power += echoes[j].power;
            if (echoes[j].power > echoes[r.strongest].power) r.strongest = std::uint32_t(j);
        }
        if (r.power >= min_power && n < kMaxGroups) groups[n++] = r;
        begin = i;
    }
    *detected = int(n);
    if (n == 0) return 0;
    std::size_t first = 0, count = 1;
    switch (mode) {
        case ReturnMode::First: break;
        case ReturnMode::Last: first = n - 1; break;
        case ReturnMode::Strongest:
            for (std::size_t g = 1; g < n; ++g)
                if (groups[g].power > groups[first].power) first = g;
            break;
        case ReturnMode::All: count = std::min<std::size_t>(n, std::size_t(max_returns)); break;
    }
    count = std::min(count, out.size());
    for (std::size_t g = 0; g < count; ++g) out[g] = groups[first + g];
    *first_rank = int(first) + 1;
    return count;
}

}  // namespace sim::sensor_model
