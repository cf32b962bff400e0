// core/height_span.hpp: the span of a cloud's heights without its stray returns. Real
// surveys carry a few returns from birds, clouds or multipath, hundreds of metres above
// or below everything else; a colour map stretched over them shows the whole survey in
// one colour. The span here leaves out a tail of at most a thousandth of the heights
// when an empty gap parts it from the rest, and is the heights' own span otherwise.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <unordered_map>

namespace core {

/// The least gap, in metres, that parts stray returns from the rest of a survey's heights
/// where a colour range is chosen (the viewer's height colours, `ground --whiten`).
inline constexpr double kStrayGap_m = 20.0;

/// A histogram of heights in bins of min_gap / 64, each with its count and its lowest
/// and highest height. Only the bins that hold a height are kept; when they would be more
/// than kMaxBins, the width doubles as often as it takes to bring them back. Memory stays
/// under kMaxBins + 1 bins whatever the heights (a return at 10^30 is one bin), and the
/// bins, hence the span, depend only on the heights added, not on their order.
class HeightSpan {
  public:
    static constexpr std::int64_t kMaxBins = 8192;

    /// `min_gap`: the least gap, in the heights' units, that can part a stray tail from
    /// the rest (callers pass 20 m in their units). Needs a finite min_gap > 0.
    explicit HeightSpan(double min_gap);
    HeightSpan(const HeightSpan& other) { *this = other; }
    HeightSpan& operator=(const HeightSpan& other) {
        min_gap_ = other.min_gap_;
        width_ = other.width_;
        per_width_ = other.per_width_;
        bins_ = other.bins_;
        count_ = other.count_;
        sample_body_ = other.sample_body_;
        sample_calls_ = other.sample_calls_;
        last_ = nullptr;  // it pointed into the other's bins
        return *this;
    }

    /// Not-a-number and infinite heights are skipped. Inline, with the bin added to last
    /// kept at hand: callers add every point of a cloud, and near heights come in runs.
    void add(float z) { add(z, 1); }
    /// `z` counted `weight` times (a sample standing for the heights beside it).
    void add(float z, std::uint64_t weight) {
        if (!std::isfinite(z)) return;
        // Far beyond any height a key can hold: clamped, so the keys cannot overflow.
        const auto key = std::int64_t(std::clamp(std::floor(double(z) * per_width_), -1e15, 1e15));
        count_ += weight;
        if (last_ && key == last_key_) {
            last_->n += weight;
            last_->lo = std::min(last_->lo, z);
            last_->hi = std::max(last_->hi, z);
            return;
        }
        put(key, Bin{weight, z, z});
    }
    /// The heights of another span with the same min_gap (threads that gathered apart).
    void merge(const HeightSpan& other);
    std::size_t count() const { return count_; }

    struct Span {
        double lo = 0, hi = 0;        // the body's lowest and highest height
        std::size_t strays_low = 0;   // heights left out below lo
        std::size_t strays_high = 0;  // heights left out above hi
    };
    /// The body of the heights added. A tail is left out when an empty gap of at least
    /// max(min_gap, half the span of the middle 98 % of the heights) parts it from the
    /// median's side and it holds at most max(1, count / 1000) heights; of such gaps the
    /// one nearest the median cuts. Where nothing is left out, lo or hi is the lowest or
    /// highest height added, exactly. No heights: all zero.
    Span span() const { return span(min_gap_); }
    /// The same with another least gap (a reader that learns the heights' unit after
    /// reading them); the bins stay those of the constructor's min_gap.
    Span span(double min_gap) const;
    /// A sample of the heights for a caller that sees very many (the viewer's uploads):
    /// `z` is added when it lies outside the body (as read every kSampleBody calls; none
    /// before the first read); inside it, one call in `every` adds `z` counted `every`
    /// times. The strays and the body's ends stay exact, the inside is a sample, at about
    /// 1 / `every` of the cost.
    void addSampled(float z, std::uint64_t every) {
        if (sample_calls_ < kSampleBody || !(z >= sample_body_.lo && z <= sample_body_.hi))
            add(z);
        else if (sample_calls_ % every == 0)
            add(z, every);
        if (++sample_calls_ % kSampleBody == 0) sample_body_ = span();
    }
    static constexpr std::uint64_t kSampleBody = 65536;

  private:
    struct Bin {
        std::uint64_t n = 0;
        float lo = 0, hi = 0;
    };
    static void fold(Bin& into, const Bin& b);
    /// Folds `b` into the bin of `key` (at the current width), then widens the bins when
    /// they are more than kMaxBins.
    void put(std::int64_t key, const Bin& b);
    /// Doubles the bins' width `times` times, rebuilding them once.
    void widen(int times);

    double min_gap_ = 1, width_ = 1;
    double per_width_ = 1;                        // 1 / width_, halved exactly as width_ doubles
    std::unordered_map<std::int64_t, Bin> bins_;  // key: floor(height * per_width_)
    std::int64_t last_key_ = 0;                   // the bin put() touched last, for runs of near heights
    Bin* last_ = nullptr;
    std::size_t count_ = 0;
    Span sample_body_;  // addSampled's body, read every kSampleBody of its calls
    std::uint64_t sample_calls_ = 0;
};

/// The top of a colour range over heights whose highest is `highest`: the body's top
/// when strays lie above it, else `highest` itself.
inline float topWithoutStrays(const HeightSpan::Span& body, float highest) {
    return body.strays_high ? float(body.hi) : highest;
}

}  // namespace core
