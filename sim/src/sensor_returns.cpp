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

std::size_t formReturns(std::span<Echo> echoes, double resolution_m, double min_power, ReturnMode mode, int max_returns,
                        std::span<Return> out, int* detected, int* first_rank) {
    *detected = 0;
    *first_rank = 1;
    if (echoes.empty()) return 0;
    if (echoes.size() > 1)
        std::sort(echoes.begin(), echoes.end(),
                  [](const Echo& a, const Echo& b) { return a.t < b.t || (a.t == b.t && a.sub < b.sub); });
    // The pulse's returns, one group of echoes at a time, keeping only what `mode` needs
    // (no list of every group: this runs once per pulse). At most kMaxGroups are counted.
    constexpr std::size_t kMaxGroups = 64;
    const bool all = mode == ReturnMode::All;
    const std::size_t keep = all ? std::min(out.size(), std::size_t(max_returns)) : 0;
    std::size_t n = 0, kept = 0;
    Return chosen;  // first, last, strongest: the one kept, group number chosen_index
    std::size_t chosen_index = 0;
    std::size_t begin = 0;
    for (std::size_t i = 1; i <= echoes.size() && n < kMaxGroups; ++i) {
        if (i < echoes.size() && double(echoes[i].t) - double(echoes[i - 1].t) < resolution_m) continue;
        Return r;
        r.strongest = std::uint32_t(begin);
        for (std::size_t j = begin; j < i; ++j) {
            r.power += echoes[j].power;
            if (echoes[j].power > echoes[r.strongest].power) r.strongest = std::uint32_t(j);
        }
        begin = i;
        if (!(r.power >= min_power)) continue;
        if (all) {
            if (kept < keep) out[kept++] = r;
        } else if (n == 0 || mode == ReturnMode::Last || (mode == ReturnMode::Strongest && r.power > chosen.power)) {
            chosen = r;
            chosen_index = n;
        }
        ++n;
    }
    *detected = int(n);
    if (all || n == 0 || out.empty()) return kept;
    out[0] = chosen;
    *first_rank = int(chosen_index) + 1;
    return 1;
}

}  // namespace sim::sensor_model
