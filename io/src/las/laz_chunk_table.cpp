// io/src/las/laz_chunk_table.cpp: see laz_chunk_table.hpp.
//
// The coder is a 32-bit range coder with adaptive models, the one LAZ uses everywhere:
// an interval [base, base + length) narrowed by each symbol in proportion to its modelled
// probability, bytes shifted out from the top whenever length falls under 2^24, a carry
// rippling back through the bytes already out when base wraps. Its models
// (laz_models.hpp) count what they see and refresh their probabilities at growing
// intervals (the decoder's, the same models, do the same, so the two stay in step).
#include "laz_chunk_table.hpp"

#include "laz_models.hpp"

#include <core/error.hpp>

#include <algorithm>
#include <string>
#include <vector>

namespace io::detail {

using core::Error;
namespace {

constexpr std::uint32_t kMaxLength = 0xFFFFFFFFu;

class RangeEncoder {
  public:
    void encode(SymbolModel& m, std::uint32_t s) {
        const std::uint32_t before = base_;
        if (s == m.symbols() - 1) {  // the last symbol takes the rest of the interval
            const std::uint32_t x = m.low(s) * (length_ >> kLazSymbolShift);
            base_ += x;
            length_ -= x;
        } else {
            length_ >>= kLazSymbolShift;
            const std::uint32_t x = m.low(s) * length_;
            base_ += x;
            length_ = m.low(s + 1) * length_ - x;
        }
        if (before > base_) carry();
        if (length_ < kLazMinLength) renormalise();
        m.saw(s);
    }
    void encode(BitModel& m, bool bit) {
        const std::uint32_t x = m.zeroProbability() * (length_ >> kLazBitShift);
        if (!bit) {
            length_ = x;
        } else {
            const std::uint32_t before = base_;
            base_ += x;
            length_ -= x;
            if (before > base_) carry();
        }
        if (length_ < kLazMinLength) renormalise();
        m.saw(bit);
    }
    // `bits` raw bits (at most 32) of `value`, uniformly distributed.
    void raw(int bits, std::uint32_t value) {
        if (bits > 19) {
            rawPart(16, value & 0xFFFFu);
            value >>= 16;
            bits -= 16;
        }
        rawPart(bits, value);
    }
    // Closes the interval with enough bytes for a decoder to tell it apart, then the zero
    // bytes a decoder reads ahead.
    std::vector<std::uint8_t> finish() {
        const std::uint32_t before = base_;
        bool third_zero = true;
        if (length_ > 2 * kLazMinLength) {
            base_ += kLazMinLength;
            length_ = kLazMinLength >> 1;
        } else {
            base_ += kLazMinLength >> 1;
            length_ = kLazMinLength >> 9;
            third_zero = false;
        }
        if (before > base_) carry();
        renormalise();
        out_.push_back(0);
        out_.push_back(0);
        if (third_zero) out_.push_back(0);
        return std::move(out_);
    }

  private:
    void rawPart(int bits, std::uint32_t value) {
        const std::uint32_t before = base_;
        length_ >>= bits;
        base_ += value * length_;
        if (before > base_) carry();
        if (length_ < kLazMinLength) renormalise();
    }
    void carry() {
        std::size_t i = out_.size();
        while (i > 0 && out_[i - 1] == 0xFFu) out_[--i] = 0;
        if (i > 0) ++out_[i - 1];
    }
    void renormalise() {
        do {
            out_.push_back(std::uint8_t(base_ >> 24));
            base_ <<= 8;
        } while ((length_ <<= 8) < kLazMinLength);
    }

    std::uint32_t base_ = 0, length_ = kMaxLength;
    std::vector<std::uint8_t> out_;
};

// Codes 32-bit integers as corrections to a prediction: k, the number of bits of the
// correction's magnitude (interval [-(2^k - 1), 2^k]), with a model per context; then
// the position inside that interval, its top 8 bits modelled per k and the rest raw.
class IntegerCoder {
  public:
    explicit IntegerCoder(int contexts) {
        for (int c = 0; c < contexts; ++c) k_models_.emplace_back(kBits + 1);
        for (int k = 1; k <= kBits; ++k) low_models_.emplace_back(1u << std::min(k, kHighBits));
    }
    void encode(RangeEncoder& e, std::int32_t predicted, std::int32_t actual, int context) {
        const std::int32_t c = std::int32_t(std::uint32_t(actual) - std::uint32_t(predicted));
        std::uint32_t magnitude = c <= 0 ? std::uint32_t(0) - std::uint32_t(c) : std::uint32_t(c) - 1u;
        int k = 0;
        while (magnitude) {
            magnitude >>= 1;
            ++k;
        }
        e.encode(k_models_[std::size_t(context)], std::uint32_t(k));
        if (k == 0) {
            e.encode(zero_model_, c != 0);  // c is 0 or 1
            return;
        }
        if (k >= kBits)
            throw Error("LAZ chunk table: a chunk size differs from the previous one by 2^31 bytes or more");
        // Into [0, 2^k): negative corrections below 2^(k-1), positive ones above.
        const std::uint32_t at = c < 0 ? std::uint32_t(c) + ((1u << k) - 1u) : std::uint32_t(c) - 1u;
        if (k <= kHighBits) {
            e.encode(low_models_[std::size_t(k - 1)], at);
        } else {
            const int rest = k - kHighBits;
            e.encode(low_models_[std::size_t(k - 1)], at >> rest);
            e.raw(rest, at & ((1u << rest) - 1u));
        }
    }

  private:
    static constexpr int kBits = 32, kHighBits = 8;
    std::vector<SymbolModel> k_models_;    // per context, k in [0, 32]
    std::vector<SymbolModel> low_models_;  // per k >= 1
    BitModel zero_model_;                  // k = 0
};

void putU32(std::string& s, std::uint32_t v) {
    char b[4];
    for (int i = 0; i < 4; ++i) b[i] = char((v >> (8 * i)) & 0xFFu);
    s.append(b, 4);
}

}  // namespace

namespace {

// Version, count, then the coded entries: each chunk's point count (context 0) when
// `chunk_points` is given, and its byte count (context 1).
std::string codeTable(std::span<const std::uint32_t> chunk_points, std::span<const std::uint32_t> chunk_bytes) {
    std::string table;
    putU32(table, 0);  // version
    putU32(table, std::uint32_t(chunk_bytes.size()));
    if (chunk_bytes.empty()) return table;
    RangeEncoder e;
    // Two contexts as LASzip has them: 0 for point counts (tables of variable-size chunks
    // only), 1 for byte counts.
    IntegerCoder sizes(2);
    const bool variable = !chunk_points.empty();
    for (std::size_t i = 0; i < chunk_bytes.size(); ++i) {
        if (variable) {
            if (chunk_points[i] >= 0x80000000u) throw Error("LAZ chunk table: a chunk of 2^31 points or more");
            sizes.encode(e, i ? std::int32_t(chunk_points[i - 1]) : 0, std::int32_t(chunk_points[i]), 0);
        }
        if (chunk_bytes[i] >= 0x80000000u) throw Error("LAZ chunk table: a chunk of 2 GiB or more");
        sizes.encode(e, i ? std::int32_t(chunk_bytes[i - 1]) : 0, std::int32_t(chunk_bytes[i]), 1);
    }
    const std::vector<std::uint8_t> coded = e.finish();
    table.append(reinterpret_cast<const char*>(coded.data()), coded.size());
    return table;
}

}  // namespace

std::string lazChunkTable(std::span<const std::uint32_t> chunk_bytes) { return codeTable({}, chunk_bytes); }

std::string lazVariableChunkTable(std::span<const std::uint32_t> chunk_points,
                                  std::span<const std::uint32_t> chunk_bytes) {
    if (chunk_points.size() != chunk_bytes.size())
        throw Error("LAZ chunk table: " + std::to_string(chunk_points.size()) + " point counts for " +
                    std::to_string(chunk_bytes.size()) + " chunks");
    if (chunk_bytes.empty()) return codeTable({}, chunk_bytes);
    return codeTable(chunk_points, chunk_bytes);
}

}  // namespace io::detail
