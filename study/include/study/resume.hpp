// study/resume.hpp: resuming a design's session that stopped part-way (a crash, a kill,
// Ctrl-C): the same command run again finds the session's folder, checks that it holds
// this design's session of this participant, and continues at the first trial that
// trials.csv does not hold (docs/study.md "Resuming a session").
#pragma once
#include <study/design.hpp>
#include <study/study_log.hpp>

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace study {

/// What a stopped session has written.
struct ResumePoint {
    std::size_t trials_done = 0;              // rows of trials.csv: trials 1..trials_done
    std::vector<std::string> trial_rows;      // as written, header excluded
    std::vector<std::string> candidate_rows;  // those of trials 1..trials_done
    /// The later column sets trials.csv has (an older session's lacks some, and goes on
    /// without them, StudyLog::setColumns).
    TrialColumns columns = TrialColumns::Judged;
    /// Rows of questionnaires.csv (header excluded): the answers to the first
    /// questions_answered questions of questionSchedule(), kept as written.
    std::vector<std::string> questionnaire_rows;
    std::size_t questions_answered = 0;
};

/// The largest trials.csv or candidates.csv read back.
inline constexpr std::size_t kMaxResumeCsvBytes = std::size_t(64) << 20;

/// Splits one CSV line into its fields (RFC 4180 quoting, as csvCell writes it). Throws
/// core::Error("<where>: an unclosed quote") on a malformed line.
std::vector<std::string> splitCsvLine(const std::string& line, const std::string& where);

/// Checks `out` (an existing folder) for a session to resume. Returns nothing when the
/// folder holds no study file (a fresh start). Otherwise its study.json must record the
/// design with SHA-256 `design_sha256` and `session`'s participant, and every row of its
/// trials.csv must be the session's trial of that number (cloud, participant, condition,
/// block, practice, and name where the file has that column: with or without name and
/// candidates_shown, StudyLog::designTrialsHeader), and every row of its questionnaires.csv the answer to the
/// session's question of that place (questionSchedule(); participant, condition,
/// instrument, occasion, item; a rating within its range), those asked before trial
/// trials_done + 1 all there; then the trace files of later trials (the one in progress when it
/// stopped) are removed, and the rows kept are returned. Throws core::Error with one
/// line naming what does not match ("study: --out DIR holds participant P03's session;
/// allowed: ...").
std::optional<ResumePoint> findResumePoint(const std::filesystem::path& out, const std::string& design_sha256,
                                           const Design& design, const Session& session);

}  // namespace study
