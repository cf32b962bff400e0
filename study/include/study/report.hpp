// study/report.hpp: `ladarvr study report RESULTS... --out REPORT` (docs/study.md "The
// report"): the participants' session folders of one design read and checked, the
// figures per condition and per participant (hit rate, false confirmations, time to
// decision, distance to target, SSQ and raw TLX) with 95 % confidence intervals and the
// within-subject tests across conditions, the plots, and the report folder (CSV, JSON,
// PNG and one offline HTML page) written as a whole.
//
// Parts: report_read.cpp (the folders and their files), report_csv.cpp (trials.csv's
// and questionnaires.csv's text, row by row), report_sessions.cpp (which
// sessions are complete, partial or empty, and the warnings saying so), report_stats.cpp
// (the distributions, summaries and tests), report_stats_exact.cpp (the tests' exact null
// distributions), report_figures.cpp (the figures), report_plot.cpp (the PNG plots, text
// from report_font.cpp), report_html.cpp (index.html) and report_write.cpp (the CSV and
// JSON tables and the folder).
#pragma once
#include <study/instruments.hpp>

#include <array>
#include <compare>
#include <cstddef>
#include <filesystem>
#include <limits>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace study {

// ---- reading -------------------------------------------------------------------------

/// How a trial ended (trials.csv's `decision`).
enum class TrialDecision { Confirm, NoTarget, Timeout, Quit };

/// The fields of one trials.csv row the report uses (every field is checked on reading).
struct ReportTrial {
    int trial = 0;
    std::string cloud;
    TrialDecision decision = TrialDecision::Quit;
    std::optional<double> target_distance_m;
    std::optional<int> hit;  // 0 or 1; empty when the cloud has no target points
    double time_to_decision_s = 0.0;
    std::optional<double> visibility_metric;
    std::string participant, condition, block;
    bool practice = false;
    /// The plan trial's name and the candidate boxes shown; empty in a session written
    /// before trials.csv had those columns.
    std::string name;
    std::optional<int> candidates_shown;
    /// The two ways to hit (0 or 1; empty as hit is, box_hit also when no box was
    /// confirmed, and both in a session written before trials.csv had those columns).
    std::optional<int> designation_hit, box_hit;
};

/// A Likert item as it was asked: its id, its occasion (pre, post or after_condition)
/// and, after a condition, that condition (empty for pre and post).
struct LikertQuestion {
    std::string item, occasion, condition;
    auto operator<=>(const LikertQuestion&) const = default;
};

/// One participant's session as its folder holds it.
struct ParticipantResults {
    std::filesystem::path folder;
    std::string participant;
    std::vector<std::string> condition_order;  // study.json's, the order the session ran
    std::size_t trials_planned = 0;            // study.json's `order`: the session's trials
    std::vector<ReportTrial> trials;           // in trials.csv's order, practice included
    bool questionnaires = false;               // the folder has a questionnaires.csv
    std::optional<SsqScores> ssq_pre, ssq_post;
    std::map<std::string, double> tlx_raw;  // condition name -> raw TLX
    std::map<LikertQuestion, int> likert;   // the last answer to each Likert question
};

/// How much of its session a folder recorded: every trial of study.json's `order`
/// (complete), some (partial), or no trial that is not practice (empty: left out of the
/// figures and the participant count).
enum class SessionState { Complete, Partial, Empty };

/// A session folder read, whether or not its participant counts.
struct SessionRecord {
    std::filesystem::path folder;
    std::string participant;
    std::size_t trials_recorded = 0;  // trials.csv's rows, practice included
    std::size_t trials_planned = 0;   // study.json's `order`
    std::size_t practice_recorded = 0;
    SessionState state = SessionState::Complete;
};

/// Every participant of one design.
struct StudyResults {
    std::string design_sha256;
    std::vector<std::string> conditions;  // the design's condition names, sorted
    /// The sessions with a trial to count (complete or partial), by participant id.
    std::vector<ParticipantResults> participants;
    /// Every session folder read, empty ones included, by participant id.
    std::vector<SessionRecord> sessions;
};

/// A session's state from its counts: Empty without a recorded trial that is not
/// practice, Partial with fewer rows than `order` plans, else Complete.
SessionState sessionState(std::size_t recorded, std::size_t practice, std::size_t planned);
/// The session record of `p`'s folder: its counts and state.
SessionRecord sessionRecord(const ParticipantResults& p);
/// "complete", "partial" or "empty".
std::string_view sessionStateName(SessionState s);
/// The sessions in state `s`.
std::size_t countSessions(const StudyResults& results, SessionState s);
/// One warning per session that is not complete, naming its folder and what it holds:
/// "study report: DIR: no trial recorded; left out", "study report: DIR: 2 of 8 trials
/// recorded; its figures count those 2".
std::vector<std::string> sessionWarnings(const StudyResults& results);

/// The largest files read: trials.csv and questionnaires.csv, study.json.
inline constexpr std::size_t kMaxReportCsvBytes = std::size_t(64) << 20;
inline constexpr std::size_t kMaxReportRecordBytes = std::size_t(1) << 20;
/// The most participant folders one report reads.
inline constexpr std::size_t kMaxReportParticipants = 10000;

/// Whether `dir` is a participant's session folder (it holds a study.json).
bool isSessionFolder(const std::filesystem::path& dir);

/// The session folders `paths` name: each path is a session folder, or a folder whose
/// sub-folders (one level down, not through links, in name order) holding a study.json
/// are sessions. Throws core::Error("study report: <path>: ...") when a path is neither
/// or a folder holds no session.
std::vector<std::filesystem::path> findSessionFolders(const std::vector<std::filesystem::path>& paths);

/// Reads every session folder (study.json, trials.csv, questionnaires.csv when present);
/// the empty sessions are listed in `sessions` but not in `participants`. Throws
/// core::Error with one line when a folder is not a design's session, two folders are of
/// different designs (design_sha256) or hold the same participant, a row is malformed
/// ("study report: DIR/trials.csv: line 3, column hit: '2'; allowed 1, 0 or empty"), or
/// every session is empty.
StudyResults readStudyResults(const std::vector<std::filesystem::path>& session_folders);

/// The rows of a design session's trials.csv `text` (`file` names it in messages), with or
/// without the later column sets (name,candidates_shown; designation_hit,box_hit;
/// StudyLog::designTrialsHeader).
std::vector<ReportTrial> parseReportTrials(std::string_view text, const std::string& file);

/// questionnaires.csv `text` (instruments.hpp's layout) scored into `p`: the SSQ before
/// and after the session, the raw TLX per condition, the Likert answers. An item answered
/// twice counts with its last answer; an instrument with an item missing is not scored.
void parseQuestionnaires(std::string_view text, const std::string& file, ParticipantResults& p);

// ---- statistics ----------------------------------------------------------------------

namespace stats {

inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// The regularised lower and upper incomplete gamma functions P(a, x), Q(a, x) = 1 - P;
/// a > 0, x >= 0 (else NaN).
double gammaP(double a, double x);
double gammaQ(double a, double x);
/// The regularised incomplete beta function I_x(a, b); a, b > 0, 0 <= x <= 1 (else NaN).
double betaI(double x, double a, double b);
/// The chi-square distribution's upper tail P(X >= x) with `df` degrees of freedom.
double chiSquareSurvival(double x, double df);
/// Student's t distribution: P(T <= t), and the t with P(T <= t) = p (0 < p < 1).
double studentTCdf(double t, double df);
double studentTQuantile(double p, double df);
/// The standard normal distribution's P(Z <= z).
double normalCdf(double z);

/// The `q` quantile (0 <= q <= 1) of sorted `values` by linear interpolation between
/// order statistics (Hyndman and Fan's type 7, R's and numpy's default); NaN when empty.
double quantileSorted(std::span<const double> sorted, double q);

/// Mean, sample standard deviation (exactly 0 when every value is the same) and the 95 %
/// confidence interval of the mean (mean -/+ t(0.975, n-1) sd / sqrt(n)), the median and
/// the quartiles (quantileSorted); NaN where n is too small.
struct Summary {
    std::size_t n = 0;
    double mean = kNaN, sd = kNaN, ci95_low = kNaN, ci95_high = kNaN;
    double median = kNaN, q1 = kNaN, q3 = kNaN;
};
Summary summarize(std::span<const double> values);

/// A test's outcome: its name, participants n, conditions k, statistic, degrees of
/// freedom (NaN when the test has none), two-sided p (NaN when undefined, e.g. every value
/// tied), Z (the signed-rank test's standard normal deviate; NaN for Friedman), the
/// effect size and its name, and how p was found.
struct TestResult {
    std::string test;
    std::size_t n = 0;
    int k = 0;
    double statistic = kNaN, df = kNaN, p = kNaN;
    double z = kNaN;
    std::string effect;  // "rank_biserial_r" (signed-rank) or "kendall_w" (Friedman)
    double effect_size = kNaN;
    std::string p_method;  // "exact", "normal" or "chi_square"; empty when p is NaN
};

/// The most participants an exact p is counted for; above, the approximation.
inline constexpr std::size_t kMaxExactN = 50;

/// The Friedman test of `rows` (one row per participant, one column per condition, k >=
/// 2 columns): ranks within each row (ties get their average rank), the chi-square
/// statistic corrected for ties, Kendall's W = chi2 / (n (k - 1)); p exact (the
/// permutation distribution of the rank sums, each row's ranks permuted) when n <=
/// kMaxExactN and counting it stays within bounds (friedmanExactP), else from chi-square
/// with k - 1 degrees of freedom.
TestResult friedman(const std::vector<std::vector<double>>& rows);
/// The Wilcoxon signed-rank test of the pairs (a[i], b[i]): zero differences b - a dropped,
/// statistic min(W+, W-), Z = (W+ - n (n + 1) / 4) / sd with the tie correction of the
/// variance (positive when b tends to exceed a), the matched-pairs rank-biserial
/// correlation r = (W+ - W-) / (W+ + W-); p exact (every sign arrangement of the ranks,
/// ties' average ranks included, counted) when n <= kMaxExactN, else from Z (no continuity
/// correction).
TestResult wilcoxonSignedRank(std::span<const double> a, std::span<const double> b);

/// The exact two-sided p of the signed-rank statistic: `doubled_ranks` are twice the
/// ranks of the nonzero |differences| (whole numbers, ties' average ranks included),
/// `doubled_w` twice min(W+, W-). P(W <= w) over the 2^n equally likely sign arrangements,
/// doubled, at most 1.
double signedRankExactP(std::span<const int> doubled_ranks, long doubled_w);
/// The exact p of the Friedman statistic: `doubled_ranks` holds each participant's
/// within-row ranks times two (ties' average ranks included), `observed` the sum over
/// conditions of the squared doubled rank sums. P(sum >= observed) when each row's ranks
/// are permuted over the conditions, all k! orders equally likely; nullopt when counting
/// would pass the bound on distinct rank-sum states (about k = 5 with a dozen rows).
std::optional<double> friedmanExactP(const std::vector<std::vector<int>>& doubled_ranks, long long observed);

}  // namespace stats

// ---- figures ---------------------------------------------------------------------------

/// One participant's trials of one condition (or of all conditions), practice left out.
struct CellFigures {
    std::size_t trials = 0;                       // analysed trials
    std::size_t scored = 0;                       // trials with hit 0 or 1, quits left out
    std::size_t hits = 0;                         //
    std::size_t decided = 0;                      // trials ended by confirm or no_target
    double hit_rate = stats::kNaN;                // hits / scored
    double false_confirmations = stats::kNaN;     // confirms that are not hits (count)
    double time_to_decision_s = stats::kNaN;      // mean over decided trials
    double target_distance_m = stats::kNaN;       // mean over trials with a distance
    double tlx_raw = stats::kNaN;                 // the condition's raw TLX (per condition only)
    std::size_t absent = 0;                       // target-absent trials (hit empty), quits left out
    std::size_t correct_rejections = 0;           // of those, the no_target decisions
    double correct_rejection_rate = stats::kNaN;  // correct_rejections / absent
};

/// The measures compared across conditions, in report order.
std::span<const std::string_view> reportMeasures();
/// A measure's value in a cell (NaN when the cell has none).
double measureValue(const CellFigures& c, std::string_view measure);

struct CloudFigures {
    std::string cloud;
    CellFigures all;                         // every participant and condition
    double visibility_metric = stats::kNaN;  // the mean of the trials' values
};

/// The answers to one Likert question (per condition for after_condition items) over
/// the participants: how many gave each rating 1..11, and their summary.
struct LikertFigures {
    LikertQuestion question;
    std::array<std::size_t, 12> counts{};  // [rating], 1..11; [0] unused
    stats::Summary summary;
};
/// The largest Likert rating (a design's `points` is 2 to 11).
inline constexpr int kMaxLikertRating = 11;

struct ReportFigures {
    std::vector<std::string> conditions;
    std::vector<std::string> participants;
    std::vector<std::vector<CellFigures>> cells;  // [participant][condition]
    std::vector<CellFigures> participant_totals;  // [participant], all conditions
    /// [measure][condition]: the summary over participants with a value.
    std::map<std::string, std::vector<stats::Summary>, std::less<>> by_condition;
    /// [measure]: the within-subject test across conditions over complete participants.
    std::map<std::string, stats::TestResult, std::less<>> condition_tests;
    /// SSQ: [participant] pre, post (nullopt without them); summaries and post-vs-pre
    /// tests per score (nausea, oculomotor, disorientation, total).
    std::vector<std::optional<SsqScores>> ssq_pre, ssq_post;
    std::map<std::string, std::array<stats::Summary, 3>, std::less<>> ssq_summary;  // pre, post, difference
    std::map<std::string, stats::TestResult, std::less<>> ssq_tests;
    std::vector<CloudFigures> clouds;   // in name order
    std::vector<LikertFigures> likert;  // by item, occasion, condition
};

/// The SSQ scores' names, in report order, and a score by name.
std::span<const std::string_view> ssqScoreNames();
double ssqScore(const SsqScores& s, std::string_view name);

ReportFigures computeFigures(const StudyResults& results);

/// The report's tables as CSV text, by file name (conditions.csv, cells.csv,
/// participants.csv, ssq.csv, ssq_summary.csv, tests.csv, clouds.csv, likert.csv), and all
/// figures as figures.json. Numbers with nine significant digits, a value within 1e-12 of
/// 0 (rounding) written as 0 (p values as computed); an empty field (null in JSON) where
/// a figure does not apply.
std::vector<std::pair<std::string, std::string>> reportTables(const StudyResults& results,
                                                              const ReportFigures& figures);
/// index.html: the tables and the plots (linked, beside it), one page, no external resource.
std::string reportHtml(const StudyResults& results, const ReportFigures& figures);

/// The report's files: CSV tables, figures.json, the plots and index.html, by name.
std::vector<std::pair<std::string, std::string>> reportFiles(const StudyResults& results, const ReportFigures& figures);
/// The names a report folder holds (for the output-folder rules).
bool isReportFile(const std::string& name);
/// Computes the figures and writes them as the folder `out`, atomically (the previous
/// report there is replaced whole). Throws core::Error("output: ...") on failure.
void writeStudyReport(const StudyResults& results, const std::filesystem::path& out);

}  // namespace study
