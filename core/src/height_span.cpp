// core/src/height_span.cpp: the histogram of the heights (height_span.hpp), read outwards
// from the median.
#include <core/error.hpp>
#include <core/height_span.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace core {
namespace {

// Floor division by two (a key's bin at twice the width), also for negative keys.
std::int64_t half(std::int64_t k) { return k >= 0 ? k / 2 : -((-k + 1) / 2); }

// A key's bin after `times` doublings of the width.
std::int64_t shifted(std::int64_t k, int times) {
    for (int t = 0; t < times; ++t) k = half(k);
    return k;
}

}  // namespace

HeightSpan::HeightSpan(double min_gap) : min_gap_(min_gap), width_(min_gap / 64.0), per_width_(64.0 / min_gap) {
    if (!(std::isfinite(min_gap) && min_gap > 0.0))
        throw Error("HeightSpan: min_gap " + std::to_string(min_gap) + "; allowed a finite value > 0");
}

void HeightSpan::fold(Bin& into, const Bin& b) {
    if (into.n == 0) {
        into = b;
        return;
    }
    into.n += b.n;
    into.lo = std::min(into.lo, b.lo);
    into.hi = std::max(into.hi, b.hi);
}

void HeightSpan::put(std::int64_t key, const Bin& b) {
    if (last_ && key == last_key_) {
        fold(*last_, b);
        return;
    }
    Bin& t = bins_[key];
    fold(t, b);
    last_key_ = key;
    last_ = &t;
    if (std::int64_t(bins_.size()) > kMaxBins) {
        // The fewest doublings that bring the bins held back to kMaxBins.
        int times = 0;
        std::vector<std::int64_t> keys;
        keys.reserve(bins_.size());
        for (const auto& kv : bins_) keys.push_back(kv.first);
        for (;;) {
            ++times;
            for (std::int64_t& k : keys) k = half(k);
            std::sort(keys.begin(), keys.end());
            keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
            if (std::int64_t(keys.size()) <= kMaxBins) break;
        }
        widen(times);
    }
}

void HeightSpan::widen(int times) {
    if (times <= 0) return;
    std::unordered_map<std::int64_t, Bin> old;
    old.swap(bins_);
    for (int t = 0; t < times; ++t) {
        width_ *= 2.0;
        per_width_ *= 0.5;
    }
    for (const auto& [key, bin] : old) fold(bins_[shifted(key, times)], bin);
    last_ = nullptr;
}

void HeightSpan::merge(const HeightSpan& other) {
    if (other.min_gap_ != min_gap_)
        throw Error("HeightSpan::merge: min_gap " + std::to_string(other.min_gap_) + " into " +
                    std::to_string(min_gap_) + "; allowed the same");
    int times = 0;
    for (double w = width_; w < other.width_; w *= 2.0) ++times;
    widen(times);
    for (const auto& [key, bin] : other.bins_) {
        // put() may widen the bins again: each key is taken to the width of the moment.
        int other_times = 0;
        for (double w = other.width_; w < width_; w *= 2.0) ++other_times;
        put(shifted(key, other_times), bin);
    }
    count_ += other.count_;
}

HeightSpan::Span HeightSpan::span(double min_gap) const {
    Span s;
    if (count_ == 0) return s;
    std::vector<std::pair<std::int64_t, const Bin*>> sorted;
    sorted.reserve(bins_.size());
    for (const auto& [key, bin] : bins_) sorted.emplace_back(key, &bin);
    std::sort(sorted.begin(), sorted.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    std::vector<const Bin*> full;  // lowest first
    for (const auto& kb : sorted) full.push_back(kb.second);
    s.lo = full.front()->lo;
    s.hi = full.back()->hi;
    // The bin holding the height of rank q * count.
    const auto rankBin = [&](double q) {
        const double rank = q * double(count_);
        std::uint64_t seen = 0;
        for (std::size_t i = 0; i < full.size(); ++i) {
            seen += full[i]->n;
            if (double(seen) >= rank) return i;
        }
        return full.size() - 1;
    };
    const std::size_t b01 = rankBin(0.01), b99 = rankBin(0.99), median = rankBin(0.5);
    const double gap = std::max(min_gap, 0.5 * (double(full[b99]->hi) - double(full[b01]->lo)));
    const std::uint64_t max_tail = std::max<std::uint64_t>(1, count_ / 1000);

    std::uint64_t below = 0;  // the heights in full[0 .. i - 1]
    for (std::size_t i = 0; i <= median; ++i) below += full[i]->n;
    for (std::size_t i = median + 1; i < full.size(); ++i) {
        const std::uint64_t tail = count_ - below;
        if (double(full[i]->lo) - double(full[i - 1]->hi) >= gap && tail <= max_tail) {
            s.hi = full[i - 1]->hi;
            s.strays_high = tail;
            break;
        }
        below += full[i]->n;
    }
    std::uint64_t above = 0;  // the heights in full[i + 1 ..]
    for (std::size_t i = median; i < full.size(); ++i) above += full[i]->n;
    for (std::size_t i = median; i-- > 0;) {
        const std::uint64_t tail = count_ - above;
        if (double(full[i + 1]->lo) - double(full[i]->hi) >= gap && tail <= max_tail) {
            s.lo = full[i + 1]->lo;
            s.strays_low = tail;
            break;
        }
        above += full[i]->n;
    }
    return s;
}

}  // namespace core
