// study/study_folder.hpp: a study's output folder (`--out DIR`, docs/study.md "The
// files"): which names mark a folder as holding a study, the name of each trial's trace,
// and study.json, the record `--replay` reads to find a trial's cloud again.
#pragma once
#include <study/design.hpp>
#include <study/plan.hpp>

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace study {

/// "trace_<trial_number>.csv"; trials are numbered 1.. in the order they ran.
std::string traceFileName(int trial_number);

/// A name a study writes into its folder: trials.csv, candidates.csv, questionnaires.csv,
/// study.json, trace_*.csv or shown_*.json.
bool isStudyFile(std::string_view name);

/// Checks that `out` (made by the caller) is a folder that holds no study yet, so one run
/// never mixes its rows with another's. Throws core::Error("study: --out DIR: not a
/// folder") or "study: --out DIR: already holds a study (<name>); allowed: a new or empty
/// folder".
void checkStudyFolder(const std::filesystem::path& out);

/// Writes DIR/study.json atomically: the plan file's absolute path and `order`, for each
/// trial in run order its index in the plan's trials (trialOrder()).
void writeStudyRecord(const std::filesystem::path& dir, const std::filesystem::path& plan_file,
                      const std::vector<int>& order);

/// Writes DIR/study.json of a design's session atomically: the design file's absolute
/// path and SHA-256, the participant, the names of the conditions in the participant's
/// order, and `order` (0, 1, ...: the session's trials run as expandSession lists them).
void writeDesignRecord(const std::filesystem::path& dir, const std::filesystem::path& design_file,
                       const std::string& design_sha256, const std::vector<std::string>& condition_names,
                       const Session& session);

/// A study as its folder records it: the plan (read again) and the order its trials ran.
struct RecordedStudy {
    Plan plan;
    std::vector<int> order;
};
/// Reads DIR/study.json (regular file, at most 1 MiB) and the plan it names (or the design,
/// whose SHA-256 must still match, expanded for the recorded participant), and checks the
/// order against the plan's trials. Throws core::Error("<what> DIR/study.json: ...")
/// naming what is wrong, or readPlan's error; `what` says who reads it ("study: --replay").
RecordedStudy readStudyRecord(const std::filesystem::path& dir, const std::string& what = "study: --replay");

/// A trial as its study folder records it: number N (1.. in run order), the folder, and
/// the plan's trial that ran (its scene or cloud file).
struct RecordedTrial {
    int number = 0;
    std::filesystem::path folder;
    PlanTrial trial;
};
/// The trial a trace file records when it lies in a study folder: `trace` named
/// trace_<N>.csv (traceFileName) beside a study.json. Nothing for another name, or
/// without a study.json beside it. Throws core::Error("<what> <trace>: ...") when that
/// study.json cannot be read (readStudyRecord) or its order has no trial N.
std::optional<RecordedTrial> recordedTraceTrial(const std::filesystem::path& trace, const std::string& what);

}  // namespace study
