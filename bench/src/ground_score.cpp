// bench/src/ground_score.cpp: see ground_score.hpp.
#include "ground_score.hpp"

#include <cstddef>

namespace bench {

GroundScore scoreGround(const std::vector<std::uint8_t>& found, const std::vector<std::uint8_t>& truth) {
    double gg = 0, go = 0, og = 0, oo = 0;  // reference x found: ground/object
    for (std::size_t i = 0; i < truth.size(); ++i) {
        if (truth[i])
            (found[i] ? gg : go) += 1;
        else
            (found[i] ? og : oo) += 1;
    }
    const double n = gg + go + og + oo;
    GroundScore s;
    s.type1 = gg + go > 0 ? 100.0 * go / (gg + go) : 0.0;
    s.type2 = og + oo > 0 ? 100.0 * og / (og + oo) : 0.0;
    s.total = n > 0 ? 100.0 * (go + og) / n : 0.0;
    const double po = n > 0 ? (gg + oo) / n : 1.0;
    const double pe = n > 0 ? ((gg + go) * (gg + og) + (og + oo) * (go + oo)) / (n * n) : 0.0;
    s.kappa = pe < 1.0 ? 100.0 * (po - pe) / (1.0 - pe) : 100.0;
    return s;
}

}  // namespace bench
