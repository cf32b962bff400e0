// The LAZ coder's adaptive models (io/src/las/laz_models.hpp): known probabilities before
// and after their first refresh, worked out from LASzip's arithmetic by hand.
#include "../../io/src/las/laz_models.hpp"

#include <doctest/doctest.h>

#include <cstdint>

using io::detail::BitModel;
using io::detail::SymbolModel;

TEST_CASE("laz_models: a fresh symbol model is uniform in 1/2^15") {
    const SymbolModel m(4);
    CHECK(m.symbols() == 4);
    CHECK(m.low(0) == 0);
    CHECK(m.low(1) == 8192);
    CHECK(m.low(2) == 16384);
    CHECK(m.low(3) == 24576);
}

TEST_CASE("laz_models: a symbol model refreshes after (n + 6) / 2 symbols, not before") {
    SymbolModel m(4);
    for (int i = 0; i < 4; ++i) m.saw(0);
    CHECK(m.low(1) == 8192);  // four seen: still the first distribution
    m.saw(0);
    // Counts 6, 1, 1, 1 of 9: each low is (2^31 / 9 * counts below) >> 16.
    const std::uint32_t scale = 0x80000000u / 9u;
    CHECK(m.low(1) == (scale * 6u) >> 16);
    CHECK(m.low(1) == 21845);
    CHECK(m.low(2) == (scale * 7u) >> 16);
    CHECK(m.low(3) == (scale * 8u) >> 16);
}

TEST_CASE("laz_models: a bit model starts at one half and follows the zeros it sees") {
    BitModel m;
    CHECK(m.zeroProbability() == 4096);
    for (int i = 0; i < 3; ++i) m.saw(false);
    CHECK(m.zeroProbability() == 4096);
    m.saw(false);  // the fourth: zeros 5 of 6
    CHECK(m.zeroProbability() == 6826);
    BitModel ones;
    for (int i = 0; i < 4; ++i) ones.saw(true);  // zeros 1 of 6
    CHECK(ones.zeroProbability() == ((0x80000000u / 6u) >> 18));
}
