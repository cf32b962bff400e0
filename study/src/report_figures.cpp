// study/src/report_figures.cpp: the study report's figures (study/report.hpp): each
// participant's trials of each condition reduced to one value per measure, the
// conditions' means with 95 % confidence intervals, medians and quartiles over
// participants, the within-subject test of each measure across conditions, the SSQ before
// and after, the clouds, and the Likert answers per question and condition.
#include <study/report.hpp>

#include <algorithm>
#include <cmath>
#include <map>

namespace study {

namespace {
constexpr std::array<std::string_view, 6> kMeasures{
    "hit_rate", "false_confirmations", "time_to_decision_s", "target_distance_m", "tlx_raw", "correct_rejection_rate"};
constexpr std::array<std::string_view, 4> kSsqScores{"nausea", "oculomotor", "disorientation", "total"};

// Adds trial `t` to the running sums of `c` (`distance_sum` for the mean distance).
void add(CellFigures& c, const ReportTrial& t, double& time_sum, double& distance_sum, std::size_t& distances,
         std::size_t& false_confirms) {
    ++c.trials;
    if (t.hit && t.decision != TrialDecision::Quit) {
        ++c.scored;
        c.hits += std::size_t(*t.hit);
    }
    // A cloud without target points (hit empty): the right answer is no_target.
    if (!t.hit && t.decision != TrialDecision::Quit) {
        ++c.absent;
        if (t.decision == TrialDecision::NoTarget) ++c.correct_rejections;
    }
    // A confirm that is not a hit: away from the target, or on a cloud without one.
    if (t.decision == TrialDecision::Confirm && t.hit.value_or(0) == 0) ++false_confirms;
    if (t.decision == TrialDecision::Confirm || t.decision == TrialDecision::NoTarget) {
        ++c.decided;
        time_sum += t.time_to_decision_s;
    }
    if (t.target_distance_m) {
        distance_sum += *t.target_distance_m;
        ++distances;
    }
}

// The figures of the analysed (not practice) trials `pick` accepts.
template <typename Pick>
CellFigures cellOf(const std::vector<ReportTrial>& trials, Pick pick) {
    CellFigures c;
    double time_sum = 0.0, distance_sum = 0.0;
    std::size_t distances = 0, false_confirms = 0;
    for (const ReportTrial& t : trials)
        if (!t.practice && pick(t)) add(c, t, time_sum, distance_sum, distances, false_confirms);
    if (c.scored > 0) c.hit_rate = double(c.hits) / double(c.scored);
    if (c.absent > 0) c.correct_rejection_rate = double(c.correct_rejections) / double(c.absent);
    if (c.trials > 0) c.false_confirmations = double(false_confirms);
    if (c.decided > 0) c.time_to_decision_s = time_sum / double(c.decided);
    if (distances > 0) c.target_distance_m = distance_sum / double(distances);
    return c;
}

// The test across `k` conditions of the participants with a value in each (`complete`):
// the signed-rank test for two, Friedman's for more.
stats::TestResult acrossConditions(const std::vector<std::vector<double>>& complete, std::size_t k) {
    if (k == 2) {
        std::vector<double> a, b;
        for (const auto& row : complete) {
            a.push_back(row[0]);
            b.push_back(row[1]);
        }
        stats::TestResult r = stats::wilcoxonSignedRank(a, b);
        if (r.n == 0) r.n = complete.size();
        return r;
    }
    return stats::friedman(complete);
}
}  // namespace

std::span<const std::string_view> reportMeasures() { return kMeasures; }
std::span<const std::string_view> ssqScoreNames() { return kSsqScores; }

double measureValue(const CellFigures& c, std::string_view measure) {
    if (measure == "hit_rate") return c.hit_rate;
    if (measure == "false_confirmations") return c.false_confirmations;
    if (measure == "time_to_decision_s") return c.time_to_decision_s;
    if (measure == "target_distance_m") return c.target_distance_m;
    if (measure == "tlx_raw") return c.tlx_raw;
    if (measure == "correct_rejection_rate") return c.correct_rejection_rate;
    return stats::kNaN;
}

double ssqScore(const SsqScores& s, std::string_view name) {
    if (name == "nausea") return s.nausea;
    if (name == "oculomotor") return s.oculomotor;
    if (name == "disorientation") return s.disorientation;
    if (name == "total") return s.total;
    return stats::kNaN;
}

namespace {
// The SSQ's summaries before, after and their difference, and the post-vs-pre test, per score.
void addSsq(ReportFigures& f) {
    for (const std::string_view score : kSsqScores) {
        std::vector<double> pre, post, diff, paired_pre, paired_post;
        for (std::size_t i = 0; i < f.participants.size(); ++i) {
            if (f.ssq_pre[i]) pre.push_back(ssqScore(*f.ssq_pre[i], score));
            if (f.ssq_post[i]) post.push_back(ssqScore(*f.ssq_post[i], score));
            if (f.ssq_pre[i] && f.ssq_post[i]) {
                paired_pre.push_back(ssqScore(*f.ssq_pre[i], score));
                paired_post.push_back(ssqScore(*f.ssq_post[i], score));
                diff.push_back(paired_post.back() - paired_pre.back());
            }
        }
        f.ssq_summary.emplace(
            std::string(score),
            std::array<stats::Summary, 3>{stats::summarize(pre), stats::summarize(post), stats::summarize(diff)});
        stats::TestResult r = stats::wilcoxonSignedRank(paired_pre, paired_post);
        if (r.n == 0) r.n = diff.size();
        f.ssq_tests.emplace(std::string(score), r);
    }
}

// Per cloud: every participant's and condition's trials of it, and its visibility metric.
void addClouds(ReportFigures& f, const StudyResults& results) {
    std::vector<std::string> clouds;
    for (const ParticipantResults& p : results.participants)
        for (const ReportTrial& t : p.trials)
            if (!t.practice) clouds.push_back(t.cloud);
    std::sort(clouds.begin(), clouds.end());
    clouds.erase(std::unique(clouds.begin(), clouds.end()), clouds.end());
    for (const std::string& cloud : clouds) {
        CloudFigures c;
        c.cloud = cloud;
        std::vector<ReportTrial> all;
        double metric_sum = 0.0;
        std::size_t metrics = 0;
        for (const ParticipantResults& p : results.participants)
            for (const ReportTrial& t : p.trials)
                if (!t.practice && t.cloud == cloud) {
                    all.push_back(t);
                    if (t.visibility_metric) {
                        metric_sum += *t.visibility_metric;
                        ++metrics;
                    }
                }
        c.all = cellOf(all, [](const ReportTrial&) { return true; });
        if (metrics > 0) c.visibility_metric = metric_sum / double(metrics);
        f.clouds.push_back(std::move(c));
    }
}

// Per Likert question (and condition, for after_condition items): the count of each
// rating and the ratings' summary over participants.
void addLikert(ReportFigures& f, const StudyResults& results) {
    std::map<LikertQuestion, std::vector<double>> answers;
    for (const ParticipantResults& p : results.participants)
        for (const auto& [question, rating] : p.likert) answers[question].push_back(double(rating));
    for (const auto& [question, ratings] : answers) {
        LikertFigures l;
        l.question = question;
        for (const double r : ratings) ++l.counts[std::size_t(r)];
        l.summary = stats::summarize(ratings);
        f.likert.push_back(std::move(l));
    }
}
}  // namespace

ReportFigures computeFigures(const StudyResults& results) {
    ReportFigures f;
    f.conditions = results.conditions;
    const std::size_t k = f.conditions.size();
    for (const ParticipantResults& p : results.participants) {
        f.participants.push_back(p.participant);
        std::vector<CellFigures> row;
        for (const std::string& condition : f.conditions) {
            CellFigures c = cellOf(p.trials, [&](const ReportTrial& t) { return t.condition == condition; });
            if (const auto it = p.tlx_raw.find(condition); it != p.tlx_raw.end()) c.tlx_raw = it->second;
            row.push_back(c);
        }
        f.cells.push_back(std::move(row));
        f.participant_totals.push_back(cellOf(p.trials, [](const ReportTrial&) { return true; }));
        f.ssq_pre.push_back(p.ssq_pre);
        f.ssq_post.push_back(p.ssq_post);
    }

    for (const std::string_view measure : kMeasures) {
        std::vector<stats::Summary> per_condition;
        for (std::size_t j = 0; j < k; ++j) {
            std::vector<double> values;
            for (const auto& row : f.cells)
                if (const double v = measureValue(row[j], measure); !std::isnan(v)) values.push_back(v);
            per_condition.push_back(stats::summarize(values));
        }
        f.by_condition.emplace(std::string(measure), std::move(per_condition));
        // Within-subject: only participants with a value in every condition.
        std::vector<std::vector<double>> complete;
        for (const auto& row : f.cells) {
            std::vector<double> values;
            for (const CellFigures& c : row)
                if (const double v = measureValue(c, measure); !std::isnan(v)) values.push_back(v);
            if (values.size() == k) complete.push_back(std::move(values));
        }
        if (k >= 2) {
            stats::TestResult r = acrossConditions(complete, k);
            if (complete.empty()) r.k = int(k);
            f.condition_tests.emplace(std::string(measure), r);
        }
    }

    addSsq(f);
    addClouds(f, results);
    addLikert(f, results);
    return f;
}

}  // namespace study
