// study/study_folder.hpp: a study's output folder (`--out DIR`, docs/study.md "The
// files"): which names mark a folder as holding a study, the name of each trial's trace,
// and study.json, the record `--replay` reads to find a trial's cloud again.
#pragma once
#include <study/design.hpp>
#include <study/plan.hpp>

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace study {

/// "trace_<trial_number>.csv"; trials are numbered 1.. in the order they ran.
std::string traceFileName(int trial_number);

/// A name a study writes into its folder: trials.csv, candidates.csv, questionnaires.csv,
/// study.json or trace_*.csv.
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
/// order against the plan's trials. Throws core::Error("study: --replay
/// DIR/study.json: ...") naming what is wrong, or readPlan's error.
RecordedStudy readStudyRecord(const std::filesystem::path& dir);

}  // namespace study
