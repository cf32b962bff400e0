// study/src/report_read.cpp: the study report's inputs (study/report.hpp): the session
// folders, each one's study.json, trials.csv and questionnaires.csv, read with a bound on
// every file and checked field by field, so a report never stands on a malformed row (the
// CSV files' text is parsed in report_csv.cpp).
#include <study/report.hpp>

#include <study/design.hpp>
#include <study/study_log.hpp>

#include <core/error.hpp>
#include <io/strict_json.hpp>
#include <platform/safe_file.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <set>
#include <sys/stat.h>

namespace study {

namespace {
namespace fs = std::filesystem;

std::string shown(const fs::path& p) { return core::printable(p.string(), 400); }

bool nameIsRegular(const fs::path& p) {
    struct stat st{};
    return ::lstat(p.c_str(), &st) == 0 && S_ISREG(st.st_mode);
}
bool nameExists(const fs::path& p) {
    struct stat st{};
    return ::lstat(p.c_str(), &st) == 0;
}
}  // namespace

bool isSessionFolder(const fs::path& dir) { return nameExists(dir / "study.json"); }

std::vector<fs::path> findSessionFolders(const std::vector<fs::path>& paths) {
    std::vector<fs::path> out;
    for (const fs::path& path : paths) {
        std::error_code ec;
        if (!fs::is_directory(path, ec))
            throw core::Error("study report: " + shown(path) +
                              ": not a folder; allowed: a participant's session "
                              "folder or a folder of them");
        if (isSessionFolder(path)) {
            out.push_back(path);
            continue;
        }
        std::vector<fs::path> found;
        std::size_t entries = 0;
        for (fs::directory_iterator it(path, ec), end; !ec && it != end; it.increment(ec)) {
            if (++entries > 16 * kMaxReportParticipants)
                throw core::Error("study report: " + shown(path) + ": more than " +
                                  std::to_string(16 * kMaxReportParticipants) + " entries; allowed: fewer");
            const fs::file_status st = it->symlink_status(ec);
            if (!ec && fs::is_directory(st) && isSessionFolder(it->path())) found.push_back(it->path());
        }
        if (ec) throw core::Error("study report: " + shown(path) + ": cannot be listed: " + ec.message());
        if (found.empty())
            throw core::Error("study report: " + shown(path) +
                              ": no study.json in it nor in a folder one level "
                              "below; allowed: a participant's session folder or a "
                              "folder of them");
        std::sort(found.begin(), found.end());
        out.insert(out.end(), found.begin(), found.end());
    }
    if (out.size() > kMaxReportParticipants)
        throw core::Error("study report: " + std::to_string(out.size()) + " session folders; allowed at most " +
                          std::to_string(kMaxReportParticipants));
    return out;
}

namespace {
// A session's study.json read into a ParticipantResults (folder, participant, condition
// order, the trials planned) and its design's SHA-256, each field checked; `where` names
// the file in messages.
ParticipantResults readSessionRecord(const fs::path& dir, const std::string& where, std::string& design_sha256) {
    ParticipantResults p;
    p.folder = dir;
    const nlohmann::json record =
        io::parseStrictJson(platform::readTextFile(dir / "study.json", kMaxReportRecordBytes, where + ":"), where);
    const std::string allowed = "; allowed: the folder of a `ladarvr study DESIGN.json --participant P` session";
    for (const char* key : {"design_sha256", "participant"})
        if (!record.is_object() || !record.contains(key) || !record[key].is_string())
            throw core::Error(where + ": no '" + key + "' text: not a design's session" + allowed);
    if (!record.contains("condition_order") || !record["condition_order"].is_array() ||
        record["condition_order"].empty())
        throw core::Error(where + ": no 'condition_order' list: not a design's session" + allowed);
    for (const nlohmann::json& c : record["condition_order"]) {
        if (!c.is_string())
            throw core::Error(where + ": condition_order holds " + io::jsonTypeName(c) +
                              "; allowed: the conditions' names");
        if (!isStudyName(c.get<std::string>()))
            throw core::Error(where + ": condition_order holds '" + core::printable(c.get<std::string>(), 40) +
                              "'; allowed: the conditions' names, each " + std::string(kStudyNameRule));
        p.condition_order.push_back(c.get<std::string>());
    }
    // `order` lists the session's trials: how many a complete session records.
    if (record.contains("order")) {
        if (!record["order"].is_array())
            throw core::Error(where + ": order holds " + io::jsonTypeName(record["order"]) +
                              "; allowed: the list of the session's trials");
        p.trials_planned = record["order"].size();
    }
    design_sha256 = record["design_sha256"].get<std::string>();
    p.participant = record["participant"].get<std::string>();
    // The id goes into every table of the report: the design's rules, as `study
    // --participant` had them.
    if (!isStudyName(p.participant))
        throw core::Error(where + ": participant '" + core::printable(p.participant, 40) + "' is not an id of " +
                          std::string(kStudyNameRule) + allowed);
    return p;
}

// The session's trials.csv and questionnaires.csv, when there, read into `p`; every row's
// participant and condition checked against its study.json.
void readSessionFiles(ParticipantResults& p, const std::set<std::string>& condition_set) {
    const fs::path trials_file = p.folder / "trials.csv";
    const std::string trials_where = "study report: " + shown(trials_file);
    if (nameExists(trials_file)) {
        p.trials = parseReportTrials(platform::readTextFile(trials_file, kMaxReportCsvBytes, trials_where + ":"),
                                     trials_where);
        for (std::size_t i = 0; i < p.trials.size(); ++i) {
            const ReportTrial& t = p.trials[i];
            const std::string line = trials_where + ": line " + std::to_string(i + 2);
            if (t.participant != p.participant)
                throw core::Error(line + ", column participant: '" + core::printable(t.participant, 40) +
                                  "'; allowed '" + core::printable(p.participant, 40) + "', as study.json");
            if (!condition_set.contains(t.condition))
                throw core::Error(line + ", column condition: '" + core::printable(t.condition, 40) +
                                  "'; allowed one of study.json's condition_order");
        }
    }
    const fs::path q = p.folder / "questionnaires.csv";
    if (nameExists(q)) {
        if (!nameIsRegular(q))
            throw core::Error("study report: " + shown(q) +
                              ": not a regular file; allowed: the session's "
                              "questionnaires.csv");
        p.questionnaires = true;
        const std::string qwhere = "study report: " + shown(q);
        parseQuestionnaires(platform::readTextFile(q, kMaxReportCsvBytes, qwhere + ":"), qwhere, p);
    }
}

}  // namespace

StudyResults readStudyResults(const std::vector<fs::path>& session_folders) {
    StudyResults results;
    std::string first_record;
    std::map<std::string, fs::path> seen;
    std::set<std::string> condition_set;
    for (const fs::path& dir : session_folders) {
        const std::string where = "study report: " + shown(dir / "study.json");
        std::string sha;
        ParticipantResults p = readSessionRecord(dir, where, sha);
        if (first_record.empty()) {
            results.design_sha256 = sha;
            first_record = shown(dir / "study.json");
            condition_set.insert(p.condition_order.begin(), p.condition_order.end());
            if (condition_set.size() != p.condition_order.size())
                throw core::Error(where + ": condition_order names a condition twice; allowed: each once");
        } else {
            if (sha != results.design_sha256)
                throw core::Error(where + ": design SHA-256 " + core::printable(sha, 64) + " differs from " +
                                  first_record + "'s " + core::printable(results.design_sha256, 64) +
                                  "; allowed: the sessions of one design");
            const std::set<std::string> mine(p.condition_order.begin(), p.condition_order.end());
            if (mine != condition_set || mine.size() != p.condition_order.size())
                throw core::Error(where + ": condition_order does not hold " + first_record +
                                  "'s conditions once each; allowed: the sessions of one design");
        }
        if (const auto [it, fresh] = seen.emplace(p.participant, dir); !fresh)
            throw core::Error(where + ": participant " + core::printable(p.participant, 40) + " again (also in " +
                              shown(it->second) + "); allowed: each participant once");
        readSessionFiles(p, condition_set);
        results.sessions.push_back(sessionRecord(p));
        // An empty session has nothing to count: it is listed, and warned of, but its
        // participant is not one of the report's.
        if (results.sessions.back().state != SessionState::Empty) results.participants.push_back(std::move(p));
    }
    if (!session_folders.empty() && results.participants.empty())
        throw core::Error("study report: none of the " + std::to_string(session_folders.size()) +
                          " session(s) recorded a trial that is not practice; allowed: at least one session "
                          "with a trial to count");
    results.conditions.assign(condition_set.begin(), condition_set.end());
    std::sort(results.participants.begin(), results.participants.end(),
              [](const ParticipantResults& a, const ParticipantResults& b) { return a.participant < b.participant; });
    std::sort(results.sessions.begin(), results.sessions.end(),
              [](const SessionRecord& a, const SessionRecord& b) { return a.participant < b.participant; });
    return results;
}

}  // namespace study
