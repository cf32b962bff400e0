// Tests of study/src/report_stats.cpp: the incomplete gamma and beta functions, the
// chi-square, t and normal distributions, and the Friedman and Wilcoxon signed-rank tests
// against closed forms, tabled quantiles and worked examples.
#include <study/report.hpp>

#include <doctest/doctest.h>

#include <cmath>
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

TEST_CASE("Friedman: a perfect ordering, ties, and all tied") {
    // Three participants ranking three conditions alike: rank sums 3, 6, 9, statistic
    // 12 / (3 * 3 * 4) * 126 - 36 = 6, and P(chi2(2) >= 6) = e^-3.
    const stats::TestResult perfect = stats::friedman({{1, 2, 3}, {10, 20, 30}, {0.1, 0.2, 0.3}});
    CHECK(perfect.statistic == doctest::Approx(6.0));
    CHECK(perfect.df == 2.0);
    CHECK(perfect.p == doctest::Approx(std::exp(-3.0)).epsilon(1e-12));
    CHECK(perfect.n == 3);
    CHECK(perfect.k == 3);
    // A tie in the first row: rank sums 7.5, 5.5, 11, statistic 3.875 / (1 - 6 / 96).
    const stats::TestResult tied = stats::friedman({{1, 1, 2}, {1, 2, 3}, {2, 1, 3}, {3, 1, 2}});
    CHECK(tied.statistic == doctest::Approx(3.875 / 0.9375).epsilon(1e-12));
    CHECK(tied.p == doctest::Approx(0.12660710278908355).epsilon(1e-10));
    const stats::TestResult flat = stats::friedman({{1, 1, 1}, {2, 2, 2}});
    CHECK(std::isnan(flat.statistic));
    CHECK(std::isnan(flat.p));
    CHECK(std::isnan(stats::friedman({{1, 2, 3}}).p));  // one participant: nothing to test
}

TEST_CASE("Wilcoxon signed-rank: exact counts and the normal approximation") {
    // Five positive differences: W- = 0, p = 2 / 2^5.
    const std::vector<double> zero(6, 0.0);
    const stats::TestResult five =
        stats::wilcoxonSignedRank(std::vector<double>(5, 0.0), std::vector<double>{1, 2, 3, 4, 5});
    CHECK(five.statistic == 0.0);
    CHECK(five.p == doctest::Approx(0.0625));
    // Differences 1, 2, -3, 4, 5, 6: W- = 3; the subsets of 1..6 summing to at most 3 are
    // {}, {1}, {2}, {3}, {1, 2}: p = 2 * 5 / 64.
    const stats::TestResult six = stats::wilcoxonSignedRank(zero, std::vector<double>{1, 2, -3, 4, 5, 6});
    CHECK(six.statistic == 3.0);
    CHECK(six.n == 6);
    CHECK(six.p == doctest::Approx(10.0 / 64.0));
    // A zero difference is dropped and tied magnitudes take the normal approximation:
    // differences 1, 2, 0.5, 0, 2, 2 (scipy.stats.wilcoxon(method='approx') gives 0.0393595...).
    const stats::TestResult ties =
        stats::wilcoxonSignedRank(std::vector<double>{1, 2, 3, 4, 5, 6}, std::vector<double>{2, 4, 3.5, 4, 7, 8});
    CHECK(ties.n == 5);
    CHECK(ties.statistic == 0.0);
    CHECK(ties.p == doctest::Approx(0.039359508888249725).epsilon(1e-10));
    CHECK(std::isnan(stats::wilcoxonSignedRank(zero, zero).p));
}
