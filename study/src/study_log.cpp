// study/src/study_log.cpp: trials.csv, candidates.csv and the per-trial traces.
#include <study/study_log.hpp>

#include <study/csv_cell.hpp>
#include <study/study_folder.hpp>

#include <core/error.hpp>
#include <platform/atomic_file.hpp>
#include <platform/safe_file.hpp>

#include <cmath>
#include <numbers>

#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <unistd.h>

namespace study {

namespace {
std::string fixed(double v, int digits = 6) {
    char buffer[64];
    std::snprintf(buffer, sizeof buffer, "%.*f", digits, v);
    return buffer;
}
std::string optionalFixed(const std::optional<double>& v, int digits = 6) { return v ? fixed(*v, digits) : ""; }
}  // namespace

const char* StudyLog::candidatesHeader() { return "trial,candidate,score,verdict,t_s"; }

bool StudyLog::boxHolds(const core::Candidate& box, const glm::dvec3& point_world) {
    // Into the box's own axes: undo its yaw about +z around its centre.
    const glm::dvec3 d = point_world - box.centre_world;
    const double a = box.yaw_deg * std::numbers::pi / 180.0;
    const double u = std::cos(a) * d.x + std::sin(a) * d.y;
    const double v = -std::sin(a) * d.x + std::cos(a) * d.y;
    return std::abs(u) <= box.size_m.x / 2.0 && std::abs(v) <= box.size_m.y / 2.0 &&
           std::abs(d.z) <= box.size_m.z / 2.0;
}

StudyLog::StudyLog(std::filesystem::path dir, std::function<TrialInfo(int)> info, double hit_radius_m)
    : dir_(std::move(dir)), info_(std::move(info)), hit_radius_m_(hit_radius_m) {}

StudyLog::~StudyLog() { closeTrace(); }

void StudyLog::resumeAt(std::size_t trials_done, std::vector<std::string> trial_rows,
                        std::vector<std::string> candidate_rows) {
    offset_ = static_cast<int>(trials_done);
    trial_rows_ = std::move(trial_rows);
    candidate_rows_ = std::move(candidate_rows);
}

void StudyLog::setQuestions(std::string participant, std::vector<std::vector<ScheduledQuestion>> by_gap,
                            std::vector<std::string> rows_kept, std::chrono::steady_clock::time_point session_start) {
    participant_ = std::move(participant);
    questions_ = std::move(by_gap);
    question_rows_ = std::move(rows_kept);
    session_start_ = session_start;
}

void StudyLog::onAnswer(int gap, int question, const viewer::Answer& answer) {
    if (gap < 0 || static_cast<std::size_t>(gap) >= questions_.size() || question < 0 ||
        static_cast<std::size_t>(question) >= questions_[static_cast<std::size_t>(gap)].size())
        return;
    const ScheduledQuestion& q = questions_[static_cast<std::size_t>(gap)][static_cast<std::size_t>(question)];
    recorded_ = true;
    const double t_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - session_start_).count();
    question_rows_.push_back(questionnaireRow(participant_, q, answer.skipped ? std::string() : answer.response, t_s));
    writeAtomic("questionnaires.csv", questionnairesHeader(), question_rows_);
}

void StudyLog::writeAtomic(const std::string& name, const std::string& header, const std::vector<std::string>& rows) {
    std::string content = header + "\n";
    for (const std::string& r : rows) content += r + "\n";
    writeText(name, content);
}

void StudyLog::writeText(const std::string& name, const std::string& content) {
    try {
        platform::writeFileAtomic(dir_ / name, content);
    } catch (const std::exception& e) {
        if (error_.empty()) error_ = e.what();
    }
}

void StudyLog::closeTrace() {
    if (!trace_) return;
    if (std::fclose(trace_) != 0 && error_.empty())
        error_ = "output: " + trace_path_.string() + ": " + std::strerror(errno);
    trace_ = nullptr;
}

void StudyLog::onStart(int trial) {
    closeTrace();
    confirmed_.reset();
    recorded_ = true;
    shown_ = info_ ? info_(offset_ + trial).shown : TrialShown{};
    shown_.marks.clear();
    shown_path_ = dir_ / shownFileName(offset_ + trial + 1);
    writeText(shown_path_.filename().string(), formatTrialShown(shown_));
    trace_path_ = dir_ / traceFileName(offset_ + trial + 1);
    // A new file only, never through a link: the folder is checked for earlier studies
    // before the run, so an existing name here is someone else's file.
    const int fd = ::open(trace_path_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
    if (fd < 0 || !(trace_ = ::fdopen(fd, "w"))) {
        if (fd >= 0) ::close(fd);
        if (error_.empty()) error_ = "output: " + trace_path_.string() + ": cannot create: " + std::strerror(errno);
        return;
    }
    std::fprintf(trace_, "%.*s\n", static_cast<int>(io::kTraceHeader.size()), io::kTraceHeader.data());
}

void StudyLog::onFrame(int, const viewer::TraceSample& s) {
    if (!trace_) return;
    std::fputs(io::formatTraceRow(viewer::toTraceRow(s)).c_str(), trace_);
}

void StudyLog::onDesignate(int, double t_s, const glm::dvec3& point_world) {
    viewer::TrialMark mark;
    mark.t_s = t_s;
    mark.designated_world = point_world;
    shown_.marks.push_back(mark);
}

void StudyLog::onWithdraw(int, double t_s) {
    viewer::TrialMark mark;
    mark.t_s = t_s;
    shown_.marks.push_back(mark);
}

void StudyLog::onVerdict(int trial, double t_s, const core::Candidate& candidate, viewer::Verdict verdict) {
    if (verdict != viewer::Verdict::Unreviewed) {
        viewer::TrialMark mark;
        mark.t_s = t_s;
        mark.candidate = candidate.id;
        mark.verdict = verdict;
        shown_.marks.push_back(mark);
    }
    candidate_rows_.push_back(std::to_string(offset_ + trial + 1) + "," + csvCell(candidate.id) + "," +
                              fixed(candidate.score) + "," + csvCell(viewer::verdictName(verdict)) + "," + fixed(t_s));
    if (verdict == viewer::Verdict::Confirmed) confirmed_ = candidate;
}

void StudyLog::onEnd(int trial, const viewer::TrialOutcome& o) {
    closeTrace();
    const TrialInfo info = info_ ? info_(offset_ + trial) : TrialInfo{};
    std::string row = std::to_string(offset_ + trial + 1) + "," + csvCell(info.source) + "," +
                      csvCell(viewer::decisionName(o.decision));
    for (int i = 0; i < 3; ++i) row += "," + (o.designated_world ? fixed((*o.designated_world)[i]) : std::string());
    row += "," + optionalFixed(o.target_distance_m);
    // hit: empty when the cloud has no ground truth (nothing to hit); else 1 only for a
    // confirm whose point is within the radius (designation_hit) or whose confirmed
    // candidate box holds the target's centre (box_hit: the operator's answer is the box
    // then, wherever a designation stood), 0 otherwise. A designation still standing at
    // no_target, timeout or quit was not the operator's answer: its distance is kept, its
    // hit is 0. The target's centre: the scene's target meshes, else the cloud's target points.
    const bool confirmed = o.decision == viewer::Decision::Confirm;
    const bool near = confirmed && o.target_distance_m && *o.target_distance_m <= hit_radius_m_;
    const std::optional<glm::dvec3> centre =
        info.target_centre_world ? info.target_centre_world : o.target_centre_world;
    const bool boxed = confirmed && confirmed_ && centre && boxHolds(*confirmed_, *centre);
    row += !o.target_known ? "," : near || boxed ? ",1" : ",0";
    row += "," + optionalFixed(o.time_to_first_designation_s);
    row += "," + fixed(o.time_to_decision_s);
    row += "," + std::to_string(o.designations) + "," + std::to_string(o.mode_switches);
    row += "," + fixed(o.seconds_in_free_mode);
    row += "," + optionalFixed(info.visibility_metric);
    if (design_columns_)
        row += "," + csvCell(info.participant) + "," + csvCell(info.condition) + "," + csvCell(info.block) +
               (info.practice ? ",1" : ",0");
    if (columns_ >= TrialColumns::Named) row += "," + csvCell(info.name) + "," + std::to_string(info.candidates_shown);
    // designation_hit and box_hit: the two ways to hit, each 1 or 0 (empty as hit is, and
    // box_hit empty too when no candidate box was confirmed).
    if (columns_ >= TrialColumns::Judged) {
        row += !o.target_known ? "," : near ? ",1" : ",0";
        row += !o.target_known || !confirmed_ ? "," : boxed ? ",1" : ",0";
    }
    trial_rows_.push_back(std::move(row));
    shown_.terrain_source = o.terrain_source;
    shown_.terrain_failure = o.terrain_failure;
    // candidates.csv and the trial's marks first: a trial whose row is in trials.csv has
    // its verdicts written too, so a resumed session can trust trials.csv as the record of
    // what is done.
    if (!shown_path_.empty()) writeText(shown_path_.filename().string(), formatTrialShown(shown_));
    writeAtomic("candidates.csv", candidatesHeader(), candidate_rows_);
    writeAtomic("trials.csv", design_columns_ ? designTrialsHeader(columns_) : trialsHeader(columns_), trial_rows_);
}

}  // namespace study
