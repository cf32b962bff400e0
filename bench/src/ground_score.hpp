// bench/src/ground_score.hpp: how a ground classification agrees with reference labels, as
// the ISPRS filter test scores it (Sithole and Vosselman 2004): type I (bare earth called
// object), type II (an object called bare earth), total error (misclassified / all) and
// Cohen's kappa, all in percent. `bench ground-isprs` scores against the samples' hand
// labels, `bench ground-real` against a survey producer's classes.
#pragma once
#include <cstdint>
#include <vector>

namespace bench {

struct GroundScore {
    double type1 = 0, type2 = 0, total = 0, kappa = 0;  // percent
};

/// `found` and `truth` hold one flag per point, 1 = ground; the same length.
GroundScore scoreGround(const std::vector<std::uint8_t>& found, const std::vector<std::uint8_t>& truth);

}  // namespace bench
