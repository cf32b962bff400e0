// io/src/las/laz_models.hpp (internal): the adaptive models of LAZ's range coder, shared by
// its encoding half (laz_chunk_table.cpp, writing a chunk table) and its decoding half
// (copc/copc_parse.cpp, reading one back), as laz-perf's model.hpp serves its encoder and
// decoder: both must refresh their probabilities at the same moments to stay in step.
//
// A model counts the symbols it sees and, at growing intervals, turns the counts into
// probabilities: symbol models in units of 1/2^15 (a cumulative distribution), bit models
// in units of 1/2^13 (the probability of a zero). Counts are halved when their total
// passes the unit, so the models follow a drifting source. The arithmetic is LASzip's.
#pragma once
#include <algorithm>
#include <cstdint>
#include <vector>

namespace io::detail {

/// The coder's interval is renormalised (a byte shifted out or in) below this length.
inline constexpr std::uint32_t kLazMinLength = 1u << 24;
/// Symbol models: probabilities in 1/2^15.
inline constexpr int kLazSymbolShift = 15;
/// Bit models: probabilities in 1/2^13.
inline constexpr int kLazBitShift = 13;

/// An adaptive model of `n` symbols: counts, and the cumulative distribution they give.
class SymbolModel {
  public:
    explicit SymbolModel(std::uint32_t n) : n_(n), count_(n, 1u), cumulative_(n + 1, 0u) {
        cycle_ = n;
        refresh();
        until_refresh_ = cycle_ = (n + 6) >> 1;
    }
    std::uint32_t symbols() const { return n_; }
    /// P(symbol < s) in 1/2^15.
    std::uint32_t low(std::uint32_t s) const { return cumulative_[s]; }
    /// Counts `s`, refreshing the distribution when its interval is up.
    void saw(std::uint32_t s) {
        ++count_[s];
        if (--until_refresh_ == 0) refresh();
    }

  private:
    static constexpr std::uint32_t kMaxCount = 1u << kLazSymbolShift;

    void refresh() {
        if ((total_ += cycle_) > kMaxCount) {  // halve the counts, keeping each >= 1
            total_ = 0;
            for (std::uint32_t& c : count_) total_ += (c = (c + 1) >> 1);
        }
        const std::uint32_t scale = 0x80000000u / total_;
        std::uint32_t sum = 0;
        for (std::uint32_t k = 0; k < n_; ++k) {
            cumulative_[k] = (scale * sum) >> (31 - kLazSymbolShift);
            sum += count_[k];
        }
        cycle_ = std::min((5 * cycle_) >> 2, (n_ + 6) << 3);
        until_refresh_ = cycle_;
    }

    std::uint32_t n_;
    std::vector<std::uint32_t> count_;
    std::vector<std::uint32_t> cumulative_;
    std::uint32_t total_ = 0, cycle_ = 0, until_refresh_ = 0;
};

/// An adaptive model of one bit.
class BitModel {
  public:
    /// P(bit = 0) in 1/2^13.
    std::uint32_t zeroProbability() const { return p0_; }
    /// Counts `bit`, refreshing the probability when its interval is up.
    void saw(bool bit) {
        if (!bit) ++zeros_;
        if (--until_refresh_ != 0) return;
        if ((total_ += cycle_) > kMaxCount) {
            total_ = (total_ + 1) >> 1;
            zeros_ = (zeros_ + 1) >> 1;
            if (zeros_ == total_) ++total_;
        }
        p0_ = (zeros_ * (0x80000000u / total_)) >> (31 - kLazBitShift);
        cycle_ = std::min<std::uint32_t>((5 * cycle_) >> 2, 64);
        until_refresh_ = cycle_;
    }

  private:
    static constexpr std::uint32_t kMaxCount = 1u << kLazBitShift;

    std::uint32_t zeros_ = 1, total_ = 2, p0_ = 1u << (kLazBitShift - 1), cycle_ = 4, until_refresh_ = 4;
};

}  // namespace io::detail
