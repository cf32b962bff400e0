// Tests of study/src/report_stats.cpp and report_stats_exact.cpp: the incomplete gamma and
// beta functions, the chi-square, t and normal distributions, the summaries (median and
// quartiles, no rounding residue), and the Friedman and Wilcoxon signed-rank tests with
// their effect sizes and exact p against closed forms, tabled values, worked examples and
// brute-force counts; and report_format.hpp's numbers (a rounding residue written as 0).
#include <study/report.hpp>

#include "report_format.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <numeric>
#include <vector>

namespace stats = study::stats;

TEST_CASE("incomplete gamma: closed forms for whole and half a") {
    // P(1, x) = 1 - e^-x; Q(2, x) = e^-x (1 + x); Q(1/2, x) = erfc(sqrt(x)).
    CHECK(stats::gammaP(1.0, 2.0) == doctest::Approx(1.0 - std::exp(-2.0)).epsilon(1e-13));
    CHECK(stats::gammaQ(2.0, 5.0) == doctest::Approx(6.0 * std::exp(-5.0)).epsilon(1e-13));
    CHECK(stats::gammaQ(0.5, 2.0) == doctest::Approx(std::erfc(std::sqrt(2.0))).epsilon(1e-12));
    CHECK(stats::gammaP(3.0, 2.5) ==
          doctest::Approx(1.0 - std::exp(-2.5) * (1.0 + 2.5 + 2.5 * 2.5 / 2.0)).epsilon(1e-13));
    CHECK(stats::gammaP(3.0, 40.0) == doctest::Approx(1.0).epsilon(1e-14));  // the continued fraction's side
    CHECK(stats::gammaP(2.0, 0.0) == 0.0);
    CHECK(std::isnan(stats::gammaP(0.0, 1.0)));
    CHECK(std::isnan(stats::gammaQ(1.0, -1.0)));
}

TEST_CASE("incomplete beta: polynomials and the binomial tail") {
    CHECK(stats::betaI(0.5, 2.0, 3.0) == doctest::Approx(11.0 / 16.0).epsilon(1e-13));
    CHECK(stats::betaI(0.3, 2.0, 2.0) == doctest::Approx(3 * 0.09 - 2 * 0.027).epsilon(1e-13));
    CHECK(stats::betaI(0.37, 1.0, 1.0) == doctest::Approx(0.37).epsilon(1e-13));
    // I_p(k, n - k + 1) = P(X >= k) for X ~ Binomial(n, p): n 10, p 0.3, k 4.
    CHECK(stats::betaI(0.3, 4.0, 7.0) == doctest::Approx(0.3503892816).epsilon(1e-9));
    // The mirror I_x(a, b) = 1 - I_{1-x}(b, a) on both sides of the switch.
    CHECK(stats::betaI(0.8, 4.0, 7.0) == doctest::Approx(1.0 - stats::betaI(0.2, 7.0, 4.0)).epsilon(1e-13));
    CHECK(stats::betaI(0.0, 2.0, 3.0) == 0.0);
    CHECK(stats::betaI(1.0, 2.0, 3.0) == 1.0);
    CHECK(std::isnan(stats::betaI(1.5, 2.0, 3.0)));
}

TEST_CASE("chi-square, t and normal distributions against tabled values") {
    CHECK(stats::chiSquareSurvival(3.841458820694124, 1.0) == doctest::Approx(0.05).epsilon(1e-10));
    CHECK(stats::chiSquareSurvival(5.991464547107979, 2.0) == doctest::Approx(0.05).epsilon(1e-10));
    CHECK(stats::chiSquareSurvival(10.0, 4.0) == doctest::Approx(0.04042768199451279).epsilon(1e-12));
    CHECK(stats::chiSquareSurvival(0.0, 3.0) == 1.0);
    CHECK(stats::studentTCdf(1.0, 1.0) == doctest::Approx(0.75).epsilon(1e-13));  // Cauchy
    CHECK(stats::studentTCdf(2.0, 2.0) == doctest::Approx(0.5 + 1.0 / std::sqrt(6.0)).epsilon(1e-13));
    CHECK(stats::studentTCdf(-2.0, 2.0) == doctest::Approx(0.5 - 1.0 / std::sqrt(6.0)).epsilon(1e-13));
    const std::vector<std::pair<double, double>> t975{{1, 12.706204736174705},
                                                      {2, 4.302652729749464},
                                                      {5, 2.570581835636314},
                                                      {10, 2.228138851986274},
                                                      {30, 2.042272456301238}};
    for (const auto& [df, t] : t975) {
        CAPTURE(df);
        CHECK(stats::studentTQuantile(0.975, df) == doctest::Approx(t).epsilon(1e-10));
        CHECK(stats::studentTQuantile(0.025, df) == doctest::Approx(-t).epsilon(1e-10));
    }
    CHECK(stats::normalCdf(1.959963984540054) == doctest::Approx(0.975).epsilon(1e-13));
    CHECK(std::isnan(stats::studentTQuantile(1.0, 3.0)));
}

TEST_CASE("summary: mean, sd and the t interval") {
    const std::vector<double> v{1, 2, 3, 4};
    const stats::Summary s = stats::summarize(v);
    CHECK(s.n == 4);
    CHECK(s.mean == doctest::Approx(2.5));
    CHECK(s.sd == doctest::Approx(std::sqrt(5.0 / 3.0)));
    const double half = 3.182446305284263 * std::sqrt(5.0 / 3.0) / 2.0;  // t(0.975, 3)
    CHECK(s.ci95_low == doctest::Approx(2.5 - half).epsilon(1e-10));
    CHECK(s.ci95_high == doctest::Approx(2.5 + half).epsilon(1e-10));
    const stats::Summary one = stats::summarize(std::vector<double>{7});
    CHECK(one.mean == 7);
    CHECK(std::isnan(one.sd));
    CHECK(std::isnan(one.ci95_low));
    CHECK(std::isnan(stats::summarize(std::vector<double>{}).mean));
}

TEST_CASE("summary: medians and quartiles by linear interpolation (type 7)") {
    // numpy.percentile([1, 2, 3, 4], [25, 50, 75]) = 1.75, 2.5, 3.25.
    const stats::Summary even = stats::summarize(std::vector<double>{4, 1, 3, 2});
    CHECK(even.median == doctest::Approx(2.5));
    CHECK(even.q1 == doctest::Approx(1.75));
    CHECK(even.q3 == doctest::Approx(3.25));
    const stats::Summary odd = stats::summarize(std::vector<double>{3, 1, 2, 10, 7});
    CHECK(odd.median == 3.0);
    CHECK(odd.q1 == 2.0);
    CHECK(odd.q3 == 7.0);
    const stats::Summary one = stats::summarize(std::vector<double>{7});
    CHECK(one.median == 7.0);
    CHECK(one.q1 == 7.0);
    CHECK(one.q3 == 7.0);
    CHECK(std::isnan(stats::summarize(std::vector<double>{}).median));
    CHECK(std::isnan(stats::quantileSorted(std::vector<double>{1, 2}, 1.5)));
}

TEST_CASE("summary: equal values have sd 0 exactly, not a rounding residue") {
    // Summed, seven times 12.3 divided by 7 is not 12.3: the deviations from that mean
    // give an sd of 1.9e-15.
    const stats::Summary s = stats::summarize(std::vector<double>(7, 12.3));
    CHECK(s.mean == 12.3);
    CHECK(s.sd == 0.0);
    CHECK(s.ci95_low == 12.3);
    CHECK(s.ci95_high == 12.3);
    CHECK(stats::summarize(std::vector<double>(3, 0.1)).sd == 0.0);
}

TEST_CASE("report numbers: a value within 1e-12 of 0 is written 0, p values as computed") {
    namespace detail = study::detail;
    CHECK(detail::csvNumber(7.1e-15) == "0");
    CHECK(detail::csvNumber(-3e-13) == "0");
    CHECK(detail::csvNumber(-0.0) == "0");
    CHECK(detail::csvNumber(2e-12) == "2e-12");
    CHECK(detail::csvNumber(0.123456789012) == "0.123456789");
    CHECK(detail::csvNumber(stats::kNaN).empty());
    CHECK(detail::csvP(1.7763568394002505e-15) == "1.77635684e-15");
    CHECK(detail::shownValue(-1e-13) == 0.0);
    CHECK(!std::signbit(detail::shownValue(-1e-13)));
}

TEST_CASE("Friedman: a perfect ordering, ties, and all tied") {
    // Three participants ranking three conditions alike: rank sums 3, 6, 9, statistic
    // 12 / (3 * 3 * 4) * 126 - 36 = 6, Kendall's W = 6 / (3 * 2) = 1. Exactly: only the 6
    // of the 6^3 arrangements where every row has the same order reach it, p = 1/36
    // (Friedman's table for k 3, n 3: chi2 6.0, p 0.028; chi-square would say e^-3 = 0.050).
    const stats::TestResult perfect = stats::friedman({{1, 2, 3}, {10, 20, 30}, {0.1, 0.2, 0.3}});
    CHECK(perfect.statistic == doctest::Approx(6.0));
    CHECK(perfect.df == 2.0);
    CHECK(perfect.p == doctest::Approx(1.0 / 36.0).epsilon(1e-12));
    CHECK(perfect.p_method == "exact");
    CHECK(perfect.effect == "kendall_w");
    CHECK(perfect.effect_size == doctest::Approx(1.0));
    CHECK(std::isnan(perfect.z));
    CHECK(perfect.n == 3);
    CHECK(perfect.k == 3);
    // A tie in the first row: rank sums 7.5, 5.5, 11, statistic 3.875 / (1 - 6 / 96), W =
    // that / (4 * 2); exactly (each row's ranks permuted, 3 * 6^3 arrangements), p = 17/108.
    const stats::TestResult tied = stats::friedman({{1, 1, 2}, {1, 2, 3}, {2, 1, 3}, {3, 1, 2}});
    CHECK(tied.statistic == doctest::Approx(3.875 / 0.9375).epsilon(1e-12));
    CHECK(tied.effect_size == doctest::Approx(3.875 / 0.9375 / 8.0).epsilon(1e-12));
    CHECK(tied.p == doctest::Approx(17.0 / 108.0).epsilon(1e-12));
    CHECK(tied.p_method == "exact");
    const stats::TestResult flat = stats::friedman({{1, 1, 1}, {2, 2, 2}});
    CHECK(std::isnan(flat.statistic));
    CHECK(std::isnan(flat.p));
    CHECK(std::isnan(stats::friedman({{1, 2, 3}}).p));  // one participant: nothing to test
}

TEST_CASE("Wilcoxon signed-rank: exact counts and the normal approximation") {
    // Five positive differences: W- = 0, p = 2 / 2^5, r = 1, Z = 7.5 / sqrt(5 * 6 * 11 / 24).
    const std::vector<double> zero(6, 0.0);
    const stats::TestResult five =
        stats::wilcoxonSignedRank(std::vector<double>(5, 0.0), std::vector<double>{1, 2, 3, 4, 5});
    CHECK(five.statistic == 0.0);
    CHECK(five.p == doctest::Approx(0.0625));
    CHECK(five.effect_size == 1.0);
    CHECK(five.z == doctest::Approx(7.5 / std::sqrt(13.75)));
    // Differences 1, 2, -3, 4, 5, 6: W- = 3; the subsets of 1..6 summing to at most 3 are
    // {}, {1}, {2}, {3}, {1, 2}: p = 2 * 5 / 64.
    const stats::TestResult six = stats::wilcoxonSignedRank(zero, std::vector<double>{1, 2, -3, 4, 5, 6});
    CHECK(six.statistic == 3.0);
    CHECK(six.n == 6);
    CHECK(six.p == doctest::Approx(10.0 / 64.0));
    CHECK(six.effect_size == doctest::Approx(15.0 / 21.0));  // (W+ - W-) / (W+ + W-) = (18 - 3) / 21
    CHECK(six.z == doctest::Approx(7.5 / std::sqrt(22.75)));
    // A zero difference is dropped; tied magnitudes are counted exactly too: differences
    // 1, 2, 0.5, 0, 2, 2, all positive, p = 2 / 2^5 (scipy's normal approximation, method
    // 'approx', says 0.0394), Z with the tie correction 2.0604.
    const stats::TestResult ties =
        stats::wilcoxonSignedRank(std::vector<double>{1, 2, 3, 4, 5, 6}, std::vector<double>{2, 4, 3.5, 4, 7, 8});
    CHECK(ties.n == 5);
    CHECK(ties.statistic == 0.0);
    CHECK(ties.p == doctest::Approx(0.0625));
    CHECK(ties.p_method == "exact");
    CHECK(ties.z == doctest::Approx(7.5 / std::sqrt(13.75 - 24.0 / 48.0)));
    // Past kMaxExactN pairs: the normal approximation from Z.
    std::vector<double> a(51), b(51);
    for (std::size_t i = 0; i < a.size(); ++i) b[i] = double(i + 1) * (i % 3 == 0 ? -1.0 : 1.0);
    const stats::TestResult large = stats::wilcoxonSignedRank(a, b);
    CHECK(large.p_method == "normal");
    CHECK(large.p == doctest::Approx(2.0 * stats::normalCdf(-std::fabs(large.z))).epsilon(1e-12));
    const stats::TestResult none = stats::wilcoxonSignedRank(zero, zero);
    CHECK(std::isnan(none.p));
    CHECK(none.p_method.empty());
    CHECK(std::isnan(none.effect_size));
}

TEST_CASE("Friedman: the exact p against Friedman's table for k 3, n 4") {
    // Friedman (1937), Siegel and Castellan's table M: k 3, N 4: chi2_r 6.5, p 0.042 (= 1/24);
    // 8.0, p 0.0046 (= 1/216).
    const stats::TestResult a = stats::friedman({{1, 2, 3}, {1, 2, 3}, {1, 2, 3}, {2, 1, 3}});
    CHECK(a.statistic == doctest::Approx(6.5));
    CHECK(a.effect_size == doctest::Approx(6.5 / 8.0));
    CHECK(a.p == doctest::Approx(1.0 / 24.0).epsilon(1e-12));
    const stats::TestResult b = stats::friedman({{1, 2, 3}, {4, 5, 6}, {1, 2, 3}, {7, 8, 9}});
    CHECK(b.statistic == doctest::Approx(8.0));
    CHECK(b.p == doctest::Approx(1.0 / 216.0).epsilon(1e-12));
}

namespace {
// P(sum of squared rank sums >= observed) counted over every order of every row.
double bruteFriedmanP(const std::vector<std::vector<int>>& rows, long long observed) {
    std::vector<std::vector<std::vector<int>>> orders;
    for (std::vector<int> row : rows) {
        std::vector<std::vector<int>> all;
        std::sort(row.begin(), row.end());
        std::vector<std::size_t> idx(row.size());
        std::iota(idx.begin(), idx.end(), std::size_t(0));
        do {  // all k! orders, ties' repeats included
            std::vector<int> o;
            for (const std::size_t i : idx) o.push_back(row[i]);
            all.push_back(o);
        } while (std::next_permutation(idx.begin(), idx.end()));
        orders.push_back(all);
    }
    double total = 0.0, at_least = 0.0;
    std::vector<int> sums(rows[0].size(), 0);
    std::function<void(std::size_t)> walk = [&](std::size_t r) {
        if (r == rows.size()) {
            long long sq = 0;
            for (const int s : sums) sq += (long long)s * s;
            total += 1.0;
            if (sq >= observed) at_least += 1.0;
            return;
        }
        for (const std::vector<int>& o : orders[r]) {
            for (std::size_t j = 0; j < o.size(); ++j) sums[j] += o[j];
            walk(r + 1);
            for (std::size_t j = 0; j < o.size(); ++j) sums[j] -= o[j];
        }
    };
    walk(0);
    return at_least / total;
}
}  // namespace

TEST_CASE("Friedman: the counted distribution agrees with every arrangement enumerated") {
    // Doubled ranks of four conditions, ties in two rows: 24^4 arrangements walked one by one
    // (the sum of squared rank sums runs from 1600, all equal, to 1920).
    const std::vector<std::vector<int>> rows{{2, 4, 6, 8}, {3, 3, 6, 8}, {8, 2, 5, 5}, {4, 2, 8, 6}};
    for (const long long observed : {1600LL, 1700LL, 1750LL, 1800LL, 1850LL, 1904LL}) {
        CAPTURE(observed);
        const std::optional<double> p = stats::friedmanExactP(rows, observed);
        REQUIRE(p);
        CHECK(*p == doctest::Approx(bruteFriedmanP(rows, observed)).epsilon(1e-12));
    }
}

TEST_CASE("Friedman: chi-square where counting would take too long, and past kMaxExactN") {
    // Seven conditions: past the conditions an exact count is made for.
    std::vector<std::vector<double>> seven;
    for (int i = 0; i < 4; ++i) seven.push_back({1, 2, 3, 4, 5, 6, double(7 + i % 2)});
    seven[1][0] = 6.5;
    const stats::TestResult t7 = stats::friedman(seven);
    CHECK(t7.p_method == "chi_square");
    CHECK(t7.p == doctest::Approx(stats::chiSquareSurvival(t7.statistic, 6.0)).epsilon(1e-12));
    // Five conditions, 30 participants: too many rank-sum states to count.
    std::vector<std::vector<double>> five;
    for (int i = 0; i < 30; ++i) five.push_back({double(i % 5), double((i + 1) % 5), double((i * 2) % 5), 2.5, 9});
    CHECK(stats::friedman(five).p_method == "chi_square");
    // Three conditions, 51 participants: past kMaxExactN.
    std::vector<std::vector<double>> many;
    for (int i = 0; i < 51; ++i) many.push_back({double(i % 3), double((i + 1) % 3), double((i * 5) % 4)});
    const stats::TestResult tm = stats::friedman(many);
    CHECK(tm.n == 51);
    CHECK(tm.p_method == "chi_square");
    // Three conditions, 50 participants: counted, and near the approximation.
    many.pop_back();
    const stats::TestResult t50 = stats::friedman(many);
    CHECK(t50.p_method == "exact");
    CHECK(t50.p == doctest::Approx(stats::chiSquareSurvival(t50.statistic, 2.0)).epsilon(0.1));
}

TEST_CASE("Wilcoxon signed-rank: Z, the rank-biserial r and the exact p of a textbook example") {
    // Wikipedia's "Wilcoxon signed-rank test" example: ten pairs, one zero difference
    // dropped, |differences| 5, 5 tied (ranks 1.5), W+ = 27, W- = 18: statistic 18,
    // r = (27 - 18) / 45 = 0.2, Z = (27 - 22.5) / sqrt(9 * 10 * 19 / 24 - (2^3 - 2) / 48),
    // and p = 2 * 162 / 512 (the sign arrangements with W+ <= 18, counted by hand).
    const std::vector<double> x1{110, 122, 125, 120, 140, 124, 123, 137, 135, 145};
    const std::vector<double> x2{125, 115, 130, 140, 140, 115, 140, 125, 140, 135};
    const stats::TestResult t = stats::wilcoxonSignedRank(x1, x2);
    CHECK(t.n == 9);
    CHECK(t.statistic == 18.0);
    CHECK(t.effect == "rank_biserial_r");
    CHECK(t.effect_size == doctest::Approx(0.2));
    CHECK(t.z == doctest::Approx(4.5 / std::sqrt(71.25 - 0.125)).epsilon(1e-12));
    CHECK(t.p == doctest::Approx(81.0 / 128.0).epsilon(1e-12));
    CHECK(t.p_method == "exact");
    // The other way round: the same p, Z and r change sign.
    const stats::TestResult back = stats::wilcoxonSignedRank(x2, x1);
    CHECK(back.z == doctest::Approx(-t.z));
    CHECK(back.effect_size == doctest::Approx(-0.2));
    CHECK(back.p == doctest::Approx(t.p));
}

TEST_CASE("Wilcoxon signed-rank: two participants whose differences tie get p 0.5, not 0.157") {
    // Hit rates 0 and 0.5 for both: |differences| tie. Of the four sign arrangements one
    // has W+ = 0 and one W+ = 3: p = 2 * 1/4. The normal approximation with the tie
    // correction would say 2 * Phi(-1.5 / sqrt(1.125)) = 0.157.
    const stats::TestResult t = stats::wilcoxonSignedRank(std::vector<double>{0, 0}, std::vector<double>{0.5, 0.5});
    CHECK(t.n == 2);
    CHECK(t.p == doctest::Approx(0.5));
    CHECK(t.p_method == "exact");
    CHECK(t.z == doctest::Approx(1.5 / std::sqrt(1.125)));
    CHECK(t.effect_size == 1.0);
    // No arrangement of two ranks gives less than 0.5, tied or not.
    CHECK(stats::wilcoxonSignedRank(std::vector<double>{0, 0}, std::vector<double>{1, 2}).p == doctest::Approx(0.5));
}

TEST_CASE("Wilcoxon signed-rank: the counted distribution agrees with every sign arrangement") {
    // Doubled ranks with ties (3, 3: ranks 1.5 and 1.5; 7, 7, 7 ...): 2^8 arrangements.
    const std::vector<int> ranks{3, 3, 5, 8, 8, 12, 12, 12};
    for (long w = 0; w <= 36; w += 3) {
        CAPTURE(w);
        double at_most = 0.0;
        for (unsigned mask = 0; mask < (1u << ranks.size()); ++mask) {
            long sum = 0;
            for (std::size_t i = 0; i < ranks.size(); ++i)
                if (mask & (1u << i)) sum += ranks[i];
            if (sum <= w) at_most += 1.0;
        }
        CHECK(stats::signedRankExactP(ranks, w) == doctest::Approx(std::min(1.0, 2.0 * at_most / 256.0)));
    }
}
