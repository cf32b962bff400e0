// study/study_log.hpp: the study's files, written from the viewer's trial reports
// (viewer::TrialObserver) as they happen, so Ctrl-C or a crash loses at most the trial
// in flight:
//   trials.csv       one row per finished trial, the whole file replaced atomically at
//                    each trial's end
//   candidates.csv   each candidate's verdict and when it was given, replaced the same way
//   trace_<N>.csv    one row per frame of trial N, written as the frames come (its format:
//                    io/trace_file.hpp)
//   questionnaires.csv  a design session's answers, one row per answer, replaced
//                    atomically at each answer (study/instruments.hpp has its layout)
// Columns: viewer/trial.hpp; meanings: docs/study.md; text cells: study/csv_cell.hpp.
// Trials are numbered 1.. in the order they ran.
#pragma once
#include <viewer/trial.hpp>

#include <study/questionnaire.hpp>

#include <io/trace_file.hpp>

#include <chrono>

#include <cstdio>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace study {

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
    std::optional<glm::dvec3> target_centre_world{};
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
    /// trials.csv is written without name and candidates_shown, as sessions were before
    /// those columns came: a resumed session whose trials.csv lacks them goes on so.
    void leaveOutNameColumns() { name_columns_ = false; }
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

    /// trials.csv's header: trial .. visibility_metric, then name,candidates_shown (left
    /// out with `named` false: the layout written before those two columns came).
    static std::string trialsHeader(bool named = true);
    /// A design session's: trial .. visibility_metric, participant,condition,block,practice,
    /// then name,candidates_shown (left out with `named` false). New columns come last, so
    /// a reader that picks columns by position keeps working.
    static std::string designTrialsHeader(bool named = true);
    static const char* candidatesHeader();
    /// Whether `point_world` lies inside `box` (its size about its centre, turned by its
    /// yaw about +z; the faces count as inside).
    static bool boxHolds(const core::Candidate& box, const glm::dvec3& point_world);

  private:
    void writeAtomic(const std::string& name, const std::string& header, const std::vector<std::string>& rows);
    void closeTrace();

    std::filesystem::path dir_;
    std::function<TrialInfo(int)> info_;
    double hit_radius_m_ = 1.0;
    bool design_columns_ = false;
    bool name_columns_ = true;
    bool recorded_ = false;                     // recordedAnything()
    std::optional<core::Candidate> confirmed_;  // the box confirmed in the trial in flight
    int offset_ = 0;                            // trials written before this run (a resumed session)
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
