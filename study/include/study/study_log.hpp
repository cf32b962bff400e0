// study/study_log.hpp: the study's files, written from the viewer's trial reports
// (viewer::TrialObserver) as they happen, so Ctrl-C or a crash loses at most the trial
// in flight:
//   trials.csv       one row per finished trial, the whole file replaced atomically at
//                    each trial's end
//   candidates.csv   each candidate's verdict and when it was given, replaced the same way
//   trace_<N>.csv    one row per frame of trial N, written as the frames come (its format:
//                    io/trace_file.hpp)
//   shown_<N>.json   what trial N showed (its candidate boxes, its condition's colours)
//                    and the operator's marks (study/trial_shown.hpp), written atomically
//                    at the trial's start and again at its end
//   questionnaires.csv  a design session's answers, one row per answer, replaced
//                    atomically at each answer (study/instruments.hpp has its layout)
// Columns: viewer/trial.hpp; meanings: docs/study.md; text cells: study/csv_cell.hpp.
// Trials are numbered 1.. in the order they ran.
#pragma once
#include <viewer/trial.hpp>

#include <study/questionnaire.hpp>
#include <study/trial_shown.hpp>

#include <io/trace_file.hpp>

#include <chrono>

#include <cstdio>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace study {

/// Which of trials.csv's later column sets a file has (a session written before a set
/// came lacks it, and a resumed one goes on so): `Named` adds name,candidates_shown after
/// the others, `Judged` adds designation_hit,box_hit after those.
enum class TrialColumns { Base, Named, Judged };

/// What the log needs to know of each trial besides the viewer's reports.
struct TrialInfo {
    std::string source;                       // the cloud or scene as the plan names it
    std::optional<double> visibility_metric;  // the paper's metric for a scene trial
    // A design's session (study/design.hpp): the columns trials.csv gains then.
    std::string participant{}, condition{}, block{};  // block: empty for a practice trial
    bool practice = false;
    std::string name{};        // the plan trial's name (PlanTrial::name)
    int candidates_shown = 0;  // the candidate boxes the trial showed
    /// The centre of the target's bounds, world coordinates, where the trial knows it (a
    /// scene trial: its target meshes); a confirmed candidate box holding it is a hit.
    /// Unset: the centre of the cloud's points labelled target (TrialOutcome).
    std::optional<glm::dvec3> target_centre_world{};
    /// What the trial shows besides its cloud (its marks left empty): shown_<N>.json.
    TrialShown shown{};
};

class StudyLog : public viewer::TrialObserver {
  public:
    /// Writes into `dir` (which must exist). `info(position)` describes the trial at
    /// `position` (0-based run order of the whole study, resumed trials included);
    /// `hit_radius_m`: a confirmed designation this close to a target point hits; so does
    /// a confirmed candidate box that holds TrialInfo::target_centre_world (boxHolds).
    StudyLog(std::filesystem::path dir, std::function<TrialInfo(int)> info, double hit_radius_m);

    /// trials.csv gets the design's columns (designTrialsHeader()).
    void addDesignColumns() { design_columns_ = true; }
    /// trials.csv is written with the column sets `columns` only, as sessions were before
    /// the later ones came: a resumed session whose trials.csv lacks them goes on so.
    void setColumns(TrialColumns columns) { columns_ = columns; }
    /// Continues a study whose first `trials_done` trials are written: their rows of
    /// trials.csv and candidates.csv are kept as given, and the viewer's trial k is
    /// position trials_done + k (its number, trace and rows).
    void resumeAt(std::size_t trials_done, std::vector<std::string> trial_rows,
                  std::vector<std::string> candidate_rows);
    /// The questions this run asks, by gap of this run (viewer::TrialSource::questions),
    /// `participant`'s; `rows_kept`: questionnaires.csv's rows a stopped session wrote.
    /// Answers' time_s counts from `session_start`.
    void setQuestions(std::string participant, std::vector<std::vector<ScheduledQuestion>> by_gap,
                      std::vector<std::string> rows_kept, std::chrono::steady_clock::time_point session_start);
    ~StudyLog() override;

    void onStart(int trial) override;
    void onFrame(int trial, const viewer::TraceSample& sample) override;
    void onDesignate(int trial, double t_s, const glm::dvec3& point_world) override;
    void onWithdraw(int trial, double t_s) override;
    void onVerdict(int trial, double t_s, const core::Candidate& candidate, viewer::Verdict verdict) override;
    void onEnd(int trial, const viewer::TrialOutcome& outcome) override;
    void onAnswer(int gap, int question, const viewer::Answer& answer) override;

    /// Rows of trials.csv so far (header excluded), resumed ones included.
    std::size_t trialsWritten() const { return trial_rows_.size(); }
    /// Rows of questionnaires.csv so far (header excluded), resumed ones included.
    const std::vector<std::string>& questionRows() const { return question_rows_; }
    /// Whether this run started a trial or wrote an answer (a run that ends before either
    /// has nothing of the session to keep).
    bool recordedAnything() const { return recorded_; }
    /// The first write error, if any (the run goes on; the command reports it).
    const std::string& error() const { return error_; }

    /// trials.csv's header: trial .. visibility_metric, then name,candidates_shown and
    /// designation_hit,box_hit (as far as `columns` has them: the layouts written before
    /// the later columns came).
    static std::string trialsHeader(TrialColumns columns = TrialColumns::Judged);
    /// A design session's: trial .. visibility_metric, participant,condition,block,practice,
    /// then the later columns as trialsHeader's. New columns come last, so a reader that
    /// picks columns by position keeps working.
    static std::string designTrialsHeader(TrialColumns columns = TrialColumns::Judged);
    static const char* candidatesHeader();
    /// Whether `point_world` lies inside `box` (its size about its centre, turned by its
    /// yaw about +z; the faces count as inside).
    static bool boxHolds(const core::Candidate& box, const glm::dvec3& point_world);

  private:
    void writeAtomic(const std::string& name, const std::string& header, const std::vector<std::string>& rows);
    /// Replaces dir/name with `content` atomically; the first failure is kept in error_.
    void writeText(const std::string& name, const std::string& content);
    void closeTrace();

    std::filesystem::path dir_;
    std::function<TrialInfo(int)> info_;
    double hit_radius_m_ = 1.0;
    bool design_columns_ = false;
    TrialColumns columns_ = TrialColumns::Judged;
    bool recorded_ = false;                     // recordedAnything()
    std::optional<core::Candidate> confirmed_;  // the box confirmed in the trial in flight
    TrialShown shown_;                          // what the trial in flight shows, its marks so far
    std::filesystem::path shown_path_;
    int offset_ = 0;  // trials written before this run (a resumed session)
    std::vector<std::string> trial_rows_, candidate_rows_;
    std::string participant_;
    std::vector<std::vector<ScheduledQuestion>> questions_;
    std::vector<std::string> question_rows_;
    std::chrono::steady_clock::time_point session_start_{};
    std::FILE* trace_ = nullptr;
    std::filesystem::path trace_path_;
    std::string error_;
};

}  // namespace study
