// study/src/report_stats_exact.cpp: the exact null distributions of the report's rank
// tests (study/report.hpp), for the dozen participants of a typical study, where the
// normal and chi-square approximations are poor (two participants whose differences tie
// get p 0.157 from the normal approximation, while no sign arrangement gives less than
// 0.5). Ranks are doubled so that average ranks of ties stay whole numbers and every sum
// is counted exactly.
#include <study/report.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <unordered_map>

namespace study::stats {

namespace {
// The most conditions whose rank sums pack into one 64-bit key (10 bits each: a doubled
// rank sum is at most 2 k n <= 600 for k 6 and n kMaxExactN).
constexpr std::size_t kMaxExactConditions = 6;
constexpr int kKeyBits = 10;
// The most steps (a state times a row's order) counted before giving up for chi-square.
constexpr std::size_t kMaxFriedmanSteps = 20'000'000;

// The conditions' rank sums, sorted; the slots past k hold kUnused, above any sum, so
// they stay last when the whole array is sorted.
using Sums = std::array<int, kMaxExactConditions>;
constexpr int kUnused = (1 << kKeyBits) - 1;

Sums noSums(std::size_t k) {
    Sums out;
    out.fill(kUnused);
    for (std::size_t j = 0; j < k; ++j) out[j] = 0;
    return out;
}

std::uint64_t packKey(const Sums& sorted_sums) {
    std::uint64_t key = 0;
    for (const int s : sorted_sums) key = (key << kKeyBits) | std::uint64_t(s);
    return key;
}

Sums unpackKey(std::uint64_t key) {
    Sums out{};
    for (std::size_t j = out.size(); j-- > 0;) {
        out[j] = int(key & std::uint64_t(kUnused));
        key >>= kKeyBits;
    }
    return out;
}

// The distinct orders of `row` (a multiset of doubled ranks), each as likely as any other
// when all k! orders of the ranks are.
std::vector<std::vector<int>> distinctOrders(std::vector<int> row) {
    std::sort(row.begin(), row.end());
    std::vector<std::vector<int>> out;
    do out.push_back(row);
    while (std::next_permutation(row.begin(), row.end()));
    return out;
}
}  // namespace

double signedRankExactP(std::span<const int> doubled_ranks, long doubled_w) {
    // Under the null each rank is positive or negative with probability 1/2: count the
    // sign arrangements by the sum of their positive (doubled) ranks. With at most
    // kMaxExactN ranks the counts stay below 2^53, exact in a double.
    const long max_sum = std::accumulate(doubled_ranks.begin(), doubled_ranks.end(), 0L);
    std::vector<double> count(std::size_t(max_sum) + 1, 0.0);
    count[0] = 1.0;
    long reached = 0;
    for (const int rank : doubled_ranks) {
        reached += rank;
        for (long s = reached; s >= rank; --s) count[std::size_t(s)] += count[std::size_t(s - rank)];
    }
    double below = 0.0;
    for (long s = 0; s <= std::min(doubled_w, max_sum); ++s) below += count[std::size_t(s)];
    return std::min(1.0, 2.0 * below / std::pow(2.0, double(doubled_ranks.size())));
}

std::optional<double> friedmanExactP(const std::vector<std::vector<int>>& doubled_ranks, long long observed) {
    if (doubled_ranks.empty()) return std::nullopt;
    const std::size_t k = doubled_ranks[0].size();
    if (k < 2 || k > kMaxExactConditions || doubled_ranks.size() > kMaxExactN) return std::nullopt;
    // The state is the conditions' rank sums, sorted: every row's order is equally likely
    // whatever the columns, so which condition holds which sum does not change the
    // distribution of the statistic, and sorting merges k! states into one.
    std::unordered_map<std::uint64_t, double> states{{packKey(noSums(k)), 1.0}};
    std::size_t steps = 0;
    for (const std::vector<int>& row : doubled_ranks) {
        const std::vector<std::vector<int>> orders = distinctOrders(row);
        steps += states.size() * orders.size();
        if (steps > kMaxFriedmanSteps) return std::nullopt;
        const double weight = 1.0 / double(orders.size());
        std::unordered_map<std::uint64_t, double> next;
        next.reserve(states.size() * 4);
        for (const auto& [key, probability] : states) {
            const Sums sums = unpackKey(key);
            for (const std::vector<int>& order : orders) {
                Sums added = sums;
                for (std::size_t j = 0; j < k; ++j) added[j] += order[j];
                std::sort(added.begin(), added.end());
                next[packKey(added)] += probability * weight;
            }
        }
        states = std::move(next);
    }
    double at_least = 0.0;
    for (const auto& [key, probability] : states) {
        long long sum_sq = 0;
        const Sums sums = unpackKey(key);
        for (std::size_t j = 0; j < k; ++j) sum_sq += (long long)sums[j] * sums[j];
        if (sum_sq >= observed) at_least += probability;
    }
    return std::min(1.0, at_least);
}

}  // namespace study::stats
