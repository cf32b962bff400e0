// study/src/report_stats.cpp: the distributions and tests the study report uses
// (study/report.hpp). The incomplete gamma function by its power series below a + 1 and
// its continued fraction above; the incomplete beta function by its continued fraction
// (evaluated with the modified Lentz method), mirrored through I_x(a, b) = 1 - I_{1-x}(b, a)
// where that converges faster; Student's t from the incomplete beta function, its quantile
// by bisection. The summaries add the median and quartiles beside the mean; the tests'
// exact null distributions are counted in report_stats_exact.cpp.
#include <study/report.hpp>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <optional>

namespace study::stats {

namespace {
constexpr double kEps = 1e-15;
constexpr double kTiny = 1e-300;
constexpr int kMaxIterations = 10000;

// P(a, x) by the series x^a e^-x / Gamma(a) * sum_n x^n / (a (a+1) ... (a+n)).
double gammaSeries(double a, double x) {
    double term = 1.0 / a, sum = term;
    for (int n = 1; n < kMaxIterations; ++n) {
        term *= x / (a + n);
        sum += term;
        if (std::fabs(term) < std::fabs(sum) * kEps) break;
    }
    return sum * std::exp(-x + a * std::log(x) - std::lgamma(a));
}

// Q(a, x) by the continued fraction x^a e^-x / Gamma(a) * 1 / (x + 1 - a - 1(1-a) / (x +
// 3 - a - 2(2-a) / (x + 5 - a - ...))).
double gammaFraction(double a, double x) {
    double b = x + 1.0 - a, c = 1.0 / kTiny, d = 1.0 / b, h = d;
    for (int i = 1; i < kMaxIterations; ++i) {
        const double an = -i * (i - a);
        b += 2.0;
        d = an * d + b;
        if (std::fabs(d) < kTiny) d = kTiny;
        c = b + an / c;
        if (std::fabs(c) < kTiny) c = kTiny;
        d = 1.0 / d;
        const double step = d * c;
        h *= step;
        if (std::fabs(step - 1.0) < kEps) break;
    }
    return std::exp(-x + a * std::log(x) - std::lgamma(a)) * h;
}

// The continued fraction of I_x(a, b) (without its prefactor x^a (1-x)^b / (a B(a, b))).
double betaFraction(double x, double a, double b) {
    const double qab = a + b, qap = a + 1.0, qam = a - 1.0;
    double c = 1.0, d = 1.0 - qab * x / qap;
    if (std::fabs(d) < kTiny) d = kTiny;
    d = 1.0 / d;
    double h = d;
    for (int m = 1; m < kMaxIterations; ++m) {
        const int m2 = 2 * m;
        double aa = m * (b - m) * x / ((qam + m2) * (a + m2));
        d = 1.0 + aa * d;
        if (std::fabs(d) < kTiny) d = kTiny;
        c = 1.0 + aa / c;
        if (std::fabs(c) < kTiny) c = kTiny;
        d = 1.0 / d;
        h *= d * c;
        aa = -(a + m) * (qab + m) * x / ((a + m2) * (qap + m2));
        d = 1.0 + aa * d;
        if (std::fabs(d) < kTiny) d = kTiny;
        c = 1.0 + aa / c;
        if (std::fabs(c) < kTiny) c = kTiny;
        d = 1.0 / d;
        const double step = d * c;
        h *= step;
        if (std::fabs(step - 1.0) < kEps) break;
    }
    return h;
}

// Average ranks (1-based) of `v`; `ties` gets sum(t^3 - t) over groups of t equal values.
std::vector<double> averageRanks(const std::vector<double>& v, double& ties) {
    std::vector<std::size_t> idx(v.size());
    std::iota(idx.begin(), idx.end(), std::size_t(0));
    std::sort(idx.begin(), idx.end(), [&](std::size_t i, std::size_t j) { return v[i] < v[j]; });
    std::vector<double> rank(v.size());
    ties = 0.0;
    for (std::size_t i = 0; i < idx.size();) {
        std::size_t j = i;
        while (j + 1 < idx.size() && v[idx[j + 1]] == v[idx[i]]) ++j;
        const double r = (double(i) + double(j)) / 2.0 + 1.0;
        for (std::size_t m = i; m <= j; ++m) rank[idx[m]] = r;
        const double t = double(j - i + 1);
        ties += t * t * t - t;
        i = j + 1;
    }
    return rank;
}
}  // namespace

double gammaP(double a, double x) {
    if (!(a > 0.0) || !(x >= 0.0) || std::isinf(a)) return kNaN;
    if (x == 0.0) return 0.0;
    if (std::isinf(x)) return 1.0;
    return x < a + 1.0 ? gammaSeries(a, x) : 1.0 - gammaFraction(a, x);
}

double gammaQ(double a, double x) {
    if (!(a > 0.0) || !(x >= 0.0) || std::isinf(a)) return kNaN;
    if (x == 0.0) return 1.0;
    if (std::isinf(x)) return 0.0;
    return x < a + 1.0 ? 1.0 - gammaSeries(a, x) : gammaFraction(a, x);
}

double betaI(double x, double a, double b) {
    if (!(a > 0.0) || !(b > 0.0) || !(x >= 0.0 && x <= 1.0)) return kNaN;
    if (x == 0.0 || x == 1.0) return x;
    const double front =
        std::exp(std::lgamma(a + b) - std::lgamma(a) - std::lgamma(b) + a * std::log(x) + b * std::log1p(-x));
    if (x < (a + 1.0) / (a + b + 2.0)) return front * betaFraction(x, a, b) / a;
    return 1.0 - front * betaFraction(1.0 - x, b, a) / b;
}

double chiSquareSurvival(double x, double df) {
    if (!(df > 0.0) || std::isnan(x)) return kNaN;
    if (x <= 0.0) return 1.0;
    return gammaQ(df / 2.0, x / 2.0);
}

double studentTCdf(double t, double df) {
    if (!(df > 0.0) || std::isnan(t)) return kNaN;
    if (std::isinf(t)) return t > 0 ? 1.0 : 0.0;
    const double tail = 0.5 * betaI(df / (df + t * t), df / 2.0, 0.5);  // P(T > |t|)
    return t > 0.0 ? 1.0 - tail : tail;
}

double studentTQuantile(double p, double df) {
    if (!(p > 0.0 && p < 1.0) || !(df > 0.0)) return kNaN;
    if (p == 0.5) return 0.0;
    if (p < 0.5) return -studentTQuantile(1.0 - p, df);
    double lo = 0.0, hi = 1.0;
    while (studentTCdf(hi, df) < p && hi < 1e300) {
        lo = hi;
        hi *= 2.0;
    }
    for (int i = 0; i < 400 && hi - lo > 1e-13 * hi; ++i) {
        const double mid = 0.5 * (lo + hi);
        (studentTCdf(mid, df) < p ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
}

double normalCdf(double z) { return 0.5 * std::erfc(-z / std::sqrt(2.0)); }

double quantileSorted(std::span<const double> sorted, double q) {
    if (sorted.empty() || !(q >= 0.0 && q <= 1.0)) return kNaN;
    const double h = double(sorted.size() - 1) * q;
    const std::size_t lo = std::size_t(std::floor(h));
    if (lo + 1 >= sorted.size()) return sorted.back();
    return sorted[lo] + (h - double(lo)) * (sorted[lo + 1] - sorted[lo]);
}

Summary summarize(std::span<const double> values) {
    Summary s;
    s.n = values.size();
    if (s.n == 0) return s;
    std::vector<double> sorted(values.begin(), values.end());
    std::sort(sorted.begin(), sorted.end());
    s.median = quantileSorted(sorted, 0.5);
    s.q1 = quantileSorted(sorted, 0.25);
    s.q3 = quantileSorted(sorted, 0.75);
    // Equal values have that value as mean and no spread: summed, they would leave a
    // rounding residue (a standard deviation of 1e-15) where the answer is 0.
    const bool constant = sorted.front() == sorted.back();
    s.mean = constant ? sorted.front() : std::accumulate(values.begin(), values.end(), 0.0) / double(s.n);
    if (s.n < 2) return s;
    double ss = 0.0;
    if (!constant)
        for (const double v : values) ss += (v - s.mean) * (v - s.mean);
    s.sd = std::sqrt(ss / double(s.n - 1));
    const double half = studentTQuantile(0.975, double(s.n - 1)) * s.sd / std::sqrt(double(s.n));
    s.ci95_low = s.mean - half;
    s.ci95_high = s.mean + half;
    return s;
}

TestResult friedman(const std::vector<std::vector<double>>& rows) {
    TestResult r;
    r.test = "friedman";
    r.effect = "kendall_w";
    r.n = rows.size();
    r.k = rows.empty() ? 0 : int(rows[0].size());
    if (r.n < 2 || r.k < 2) return r;
    const double n = double(r.n), k = double(r.k);
    std::vector<double> rank_sums(rows[0].size(), 0.0);
    std::vector<std::vector<int>> doubled_ranks;
    double ties = 0.0;
    for (const std::vector<double>& row : rows) {
        double row_ties = 0.0;
        const std::vector<double> ranks = averageRanks(row, row_ties);
        std::vector<int> doubled;
        for (std::size_t j = 0; j < ranks.size(); ++j) {
            rank_sums[j] += ranks[j];
            doubled.push_back(int(std::lround(2.0 * ranks[j])));
        }
        doubled_ranks.push_back(std::move(doubled));
        ties += row_ties;
    }
    double sum_sq = 0.0;
    long long doubled_sum_sq = 0;
    for (const double rs : rank_sums) {
        sum_sq += rs * rs;
        const long long d = std::llround(2.0 * rs);
        doubled_sum_sq += d * d;
    }
    const double correction = 1.0 - ties / (n * (k * k * k - k));
    r.df = k - 1.0;
    if (correction <= 0.0) return r;  // every row tied throughout: no ranking to test
    r.statistic = (12.0 / (n * k * (k + 1.0)) * sum_sq - 3.0 * n * (k + 1.0)) / correction;
    r.effect_size = r.statistic / (n * (k - 1.0));
    const std::optional<double> exact =
        r.n <= kMaxExactN ? friedmanExactP(doubled_ranks, doubled_sum_sq) : std::nullopt;
    r.p = exact ? *exact : chiSquareSurvival(r.statistic, r.df);
    r.p_method = exact ? "exact" : "chi_square";
    return r;
}

TestResult wilcoxonSignedRank(std::span<const double> a, std::span<const double> b) {
    TestResult r;
    r.test = "wilcoxon_signed_rank";
    r.effect = "rank_biserial_r";
    r.k = 2;
    std::vector<double> magnitude;
    std::vector<bool> positive;
    for (std::size_t i = 0; i < a.size() && i < b.size(); ++i) {
        const double d = b[i] - a[i];
        if (d == 0.0) continue;
        magnitude.push_back(std::fabs(d));
        positive.push_back(d > 0.0);
    }
    r.n = magnitude.size();
    if (r.n == 0) return r;
    double ties = 0.0;
    const std::vector<double> ranks = averageRanks(magnitude, ties);
    double w_plus = 0.0;
    std::vector<int> doubled_ranks;
    for (std::size_t i = 0; i < ranks.size(); ++i) {
        if (positive[i]) w_plus += ranks[i];
        doubled_ranks.push_back(int(std::lround(2.0 * ranks[i])));
    }
    const double n = double(r.n);
    const double total = n * (n + 1.0) / 2.0;
    r.statistic = std::min(w_plus, total - w_plus);
    r.effect_size = (w_plus - (total - w_plus)) / total;
    const double var = n * (n + 1.0) * (2.0 * n + 1.0) / 24.0 - ties / 48.0;
    if (var > 0.0) r.z = (w_plus - total / 2.0) / std::sqrt(var);
    if (r.n <= kMaxExactN) {
        r.p = signedRankExactP(doubled_ranks, std::lround(2.0 * r.statistic));
        r.p_method = "exact";
    } else if (!std::isnan(r.z)) {
        r.p = std::min(1.0, 2.0 * normalCdf(-std::fabs(r.z)));
        r.p_method = "normal";
    }
    return r;
}

}  // namespace study::stats
