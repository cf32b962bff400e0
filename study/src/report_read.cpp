// study/src/report_read.cpp: the study report's inputs (study/report.hpp): the session
// folders, each one's study.json, trials.csv and questionnaires.csv, read with a bound on
// every file and checked field by field, so a report never stands on a malformed row.
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

constexpr std::string_view kQuestionnairesHeader = "participant,condition,instrument,occasion,item,response,time_s";

std::string shown(const fs::path& p) { return core::printable(p.string(), 400); }

/// One CSV record and the line it starts on.
struct CsvRecord {
    std::size_t line = 0;
    std::vector<std::string> fields;
};

// The records of CSV `text` (RFC 4180: a quoted field may hold commas, doubled quotes and
// line breaks; a carriage return before a line break is dropped; the last line may lack
// its line break). An empty line is an error, as is a quote inside an unquoted field.
std::vector<CsvRecord> csvRecords(std::string_view text, const std::string& file) {
    std::vector<CsvRecord> out;
    std::size_t line = 1, i = 0;
    while (i < text.size()) {
        CsvRecord rec;
        rec.line = line;
        rec.fields.emplace_back();
        bool quoted = false, was_quoted = false, ended = false;
        while (i < text.size()) {
            const char c = text[i];
            if (quoted) {
                if (c == '"' && i + 1 < text.size() && text[i + 1] == '"') {
                    rec.fields.back() += '"';
                    i += 2;
                    continue;
                }
                if (c == '"') {
                    quoted = false;
                } else {
                    if (c == '\n') ++line;
                    rec.fields.back() += c;
                }
                ++i;
                continue;
            }
            if (c == '"') {
                if (!rec.fields.back().empty() || was_quoted)
                    throw core::Error(file + ": line " + std::to_string(line) +
                                      ": a quote inside an unquoted field; allowed: RFC 4180 quoting");
                quoted = was_quoted = true;
            } else if (c == ',') {
                rec.fields.emplace_back();
                was_quoted = false;
            } else if (c == '\r' && i + 1 < text.size() && text[i + 1] == '\n') {
                // dropped: a CRLF line end
            } else if (c == '\n') {
                ++i;
                ++line;
                ended = true;
                break;
            } else {
                if (was_quoted)
                    throw core::Error(file + ": line " + std::to_string(line) +
                                      ": text after a closing quote; allowed: RFC 4180 quoting");
                rec.fields.back() += c;
            }
            ++i;
        }
        if (quoted) throw core::Error(file + ": line " + std::to_string(rec.line) + ": an unclosed quote");
        if (rec.fields.size() == 1 && rec.fields[0].empty() && !was_quoted)
            throw core::Error(file + ": line " + std::to_string(rec.line) + ": an empty line; allowed: none");
        (void)ended;
        out.push_back(std::move(rec));
    }
    return out;
}

[[noreturn]] void badField(const std::string& file, std::size_t line, std::string_view column, const std::string& value,
                           std::string_view allowed) {
    throw core::Error(file + ": line " + std::to_string(line) + ", column " + std::string(column) + ": '" +
                      core::printable(value, 60) + "'; allowed " + std::string(allowed));
}

// The largest times (seconds) and distances (metres) a row may hold.
constexpr double kMaxSeconds = 1e9;
constexpr double kMaxMetres = 1e12;
constexpr long long kMaxCount = 1000000000;

// "lo .. hi" as the bounds read in a message: the same numbers the check uses, written
// short (1e9, not 1e+09).
std::string between(double lo, double hi) {
    const auto shortNumber = [](double v) {
        char buf[32];
        std::snprintf(buf, sizeof buf, "%g", v);
        std::string out = buf;
        if (const std::size_t e = out.find("e+"); e != std::string::npos) {
            std::size_t digits = e + 2;
            while (digits + 1 < out.size() && out[digits] == '0') ++digits;
            out = out.substr(0, e + 1) + out.substr(digits);
        }
        return out;
    };
    return shortNumber(lo) + " .. " + shortNumber(hi);
}

// A plain decimal number (no spaces, no '+'), finite.
std::optional<double> decimal(const std::string& s) {
    if (s.empty() || s[0] == '+') return std::nullopt;
    double v = 0.0;
    const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (ec != std::errc() || ptr != s.data() + s.size() || !std::isfinite(v)) return std::nullopt;
    return v;
}

std::optional<long long> wholeNumber(const std::string& s) {
    long long v = 0;
    const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (s.empty() || ec != std::errc() || ptr != s.data() + s.size()) return std::nullopt;
    return v;
}

struct RowReader {
    const std::string& file;
    const CsvRecord& rec;
    const std::vector<std::string>& columns;

    const std::string& at(std::size_t i) const { return rec.fields[i]; }
    [[noreturn]] void bad(std::size_t i, std::string_view allowed) const {
        badField(file, rec.line, columns[i], rec.fields[i], allowed);
    }
    double number(std::size_t i, double lo, double hi, std::string_view allowed) const {
        const std::optional<double> v = decimal(at(i));
        if (!v || *v < lo || *v > hi) bad(i, allowed);
        return *v;
    }
    std::optional<double> optionalNumber(std::size_t i, double lo, double hi, std::string_view allowed) const {
        if (at(i).empty()) return std::nullopt;
        return number(i, lo, hi, allowed);
    }
    long long whole(std::size_t i, long long lo, long long hi, std::string_view allowed) const {
        const std::optional<long long> v = wholeNumber(at(i));
        if (!v || *v < lo || *v > hi) bad(i, allowed);
        return *v;
    }
};

std::vector<std::string> splitHeader(std::string_view header) {
    std::vector<std::string> out(1);
    for (const char c : header) {
        if (c == ',')
            out.emplace_back();
        else
            out.back() += c;
    }
    return out;
}

bool nameIsRegular(const fs::path& p) {
    struct stat st{};
    return ::lstat(p.c_str(), &st) == 0 && S_ISREG(st.st_mode);
}
bool nameExists(const fs::path& p) {
    struct stat st{};
    return ::lstat(p.c_str(), &st) == 0;
}
}  // namespace

std::vector<ReportTrial> parseReportTrials(std::string_view text, const std::string& file) {
    const std::vector<CsvRecord> records = csvRecords(text, file);
    const std::string header = StudyLog::designTrialsHeader();
    if (records.empty()) throw core::Error(file + ": empty; allowed: a design session's trials.csv");
    std::string first;
    for (std::size_t i = 0; i < records[0].fields.size(); ++i) first += (i ? "," : "") + records[0].fields[i];
    // Sessions written before the later column sets came lack them.
    std::optional<TrialColumns> layout;
    for (const TrialColumns c : {TrialColumns::Base, TrialColumns::Named, TrialColumns::Judged})
        if (first == StudyLog::designTrialsHeader(c)) layout = c;
    if (!layout)
        throw core::Error(file + ": line 1: not the header of a design session's trials.csv; allowed: " + header +
                          " (or the same without designation_hit,box_hit, or without name,candidates_shown too)");
    const bool named = *layout >= TrialColumns::Named;
    const std::vector<std::string> columns = splitHeader(first);
    enum : std::size_t {
        kTrial,
        kCloud,
        kDecision,
        kX,
        kY,
        kZ,
        kDistance,
        kHit,
        kFirst,
        kTime,
        kDesignations,
        kSwitches,
        kFree,
        kMetric,
        kParticipant,
        kCondition,
        kBlock,
        kPractice,
        kName,
        kCandidatesShown,
        kDesignationHit,
        kBoxHit
    };
    std::vector<ReportTrial> out;
    for (std::size_t r = 1; r < records.size(); ++r) {
        const CsvRecord& rec = records[r];
        if (rec.fields.size() != columns.size())
            throw core::Error(file + ": line " + std::to_string(rec.line) + ": " + std::to_string(rec.fields.size()) +
                              " fields; allowed: " + std::to_string(columns.size()) + ", as the header");
        const RowReader row{file, rec, columns};
        ReportTrial t;
        t.trial = int(row.whole(kTrial, long(r), long(r),
                                "the row's number " + std::to_string(r) + " (trials are numbered 1, 2, ... in order)"));
        t.cloud = row.at(kCloud);
        if (t.cloud.empty()) row.bad(kCloud, "the trial's cloud or scene file");
        const std::string& d = row.at(kDecision);
        if (d == "confirm")
            t.decision = TrialDecision::Confirm;
        else if (d == "no_target")
            t.decision = TrialDecision::NoTarget;
        else if (d == "timeout")
            t.decision = TrialDecision::Timeout;
        else if (d == "quit")
            t.decision = TrialDecision::Quit;
        else
            row.bad(kDecision, "confirm, no_target, timeout or quit");
        const bool xyz_empty = row.at(kX).empty() && row.at(kY).empty() && row.at(kZ).empty();
        if (!xyz_empty)
            for (const std::size_t c : {kX, kY, kZ})
                row.number(c, -kMaxMetres, kMaxMetres,
                           "three numbers " + between(-kMaxMetres, kMaxMetres) + " (metres) or three empty fields");
        t.target_distance_m =
            row.optionalNumber(kDistance, 0.0, kMaxMetres, "a number " + between(0, kMaxMetres) + " (metres) or empty");
        if (!row.at(kHit).empty()) t.hit = int(row.whole(kHit, 0, 1, "1, 0 or empty"));
        const std::string seconds = "a number " + between(0, kMaxSeconds) + " (seconds)";
        row.optionalNumber(kFirst, 0.0, kMaxSeconds, seconds + " or empty");
        t.time_to_decision_s = row.number(kTime, 0.0, kMaxSeconds, seconds);
        const std::string count = "a whole number " + between(0, double(kMaxCount));
        row.whole(kDesignations, 0, kMaxCount, count);
        row.whole(kSwitches, 0, kMaxCount, count);
        row.number(kFree, 0.0, kMaxSeconds, seconds);
        t.visibility_metric = row.optionalNumber(kMetric, 0.0, 1.0, "a number in [0, 1] or empty");
        t.participant = row.at(kParticipant);
        if (t.participant.empty()) row.bad(kParticipant, "the participant's id");
        t.condition = row.at(kCondition);
        if (t.condition.empty()) row.bad(kCondition, "a condition's name");
        t.practice = row.whole(kPractice, 0, 1, "1 (a practice trial) or 0") == 1;
        t.block = row.at(kBlock);
        if (!t.block.empty() && !isStudyName(t.block))
            row.bad(kBlock, "a block's name, " + std::string(kStudyNameRule));
        if (t.practice != t.block.empty())
            row.bad(kBlock,
                    t.practice ? "empty for a practice trial" : "a block's name for a trial that is not practice");
        if (named) {
            t.name = row.at(kName);
            if (t.name.empty()) row.bad(kName, "the trial's name");
            t.candidates_shown = int(row.whole(kCandidatesShown, 0, kMaxCount, count));
        }
        if (*layout == TrialColumns::Judged) {
            if (!row.at(kDesignationHit).empty())
                t.designation_hit = int(row.whole(kDesignationHit, 0, 1, "1, 0 or empty"));
            if (!row.at(kBoxHit).empty()) t.box_hit = int(row.whole(kBoxHit, 0, 1, "1, 0 or empty"));
        }
        out.push_back(std::move(t));
    }
    return out;
}

void parseQuestionnaires(std::string_view text, const std::string& file, ParticipantResults& p) {
    const std::vector<CsvRecord> records = csvRecords(text, file);
    std::string first;
    if (!records.empty())
        for (std::size_t i = 0; i < records[0].fields.size(); ++i) first += (i ? "," : "") + records[0].fields[i];
    if (first != kQuestionnairesHeader)
        throw core::Error(
            file + ": line 1: not the header of questionnaires.csv; allowed: " + std::string(kQuestionnairesHeader));
    const std::vector<std::string> columns = splitHeader(kQuestionnairesHeader);
    enum : std::size_t { kParticipant, kCondition, kInstrument, kOccasion, kItem, kResponse, kTime };
    const std::set<std::string> conditions(p.condition_order.begin(), p.condition_order.end());
    // The last answer of each item: SSQ per occasion, TLX per condition.
    std::array<std::array<std::optional<int>, kSsqItemCount>, 2> ssq{};
    std::map<std::string, std::array<std::optional<int>, kTlxItemCount>> tlx;
    for (std::size_t r = 1; r < records.size(); ++r) {
        const CsvRecord& rec = records[r];
        if (rec.fields.size() != columns.size())
            throw core::Error(file + ": line " + std::to_string(rec.line) + ": " + std::to_string(rec.fields.size()) +
                              " fields; allowed: " + std::to_string(columns.size()) + ", as the header");
        const RowReader row{file, rec, columns};
        if (row.at(kParticipant) != p.participant) row.bad(kParticipant, "'" + p.participant + "', as study.json");
        const std::string& instrument = row.at(kInstrument);
        const std::string& occasion = row.at(kOccasion);
        const std::string& condition = row.at(kCondition);
        if (occasion != "pre" && occasion != "post" && occasion != "after_condition")
            row.bad(kOccasion, "pre, post or after_condition");
        if (occasion == "pre" && !condition.empty()) row.bad(kCondition, "empty with occasion pre");
        if (!condition.empty() && !conditions.contains(condition))
            row.bad(kCondition, "one of the session's conditions (study.json's condition_order) or empty");
        row.number(kTime, 0.0, kMaxSeconds,
                   "a number " + between(0, kMaxSeconds) + " (seconds from the start of the session)");
        if (instrument == "ssq") {
            if (occasion == "after_condition") row.bad(kOccasion, "pre or post for the SSQ");
            const std::optional<int> item = ssqItemIndex(row.at(kItem));
            if (!item) row.bad(kItem, "one of the SSQ's 16 symptom ids (study/instruments.hpp)");
            ssq[occasion == "pre" ? 0 : 1][std::size_t(*item)] =
                int(row.whole(kResponse, 0, kSsqMaxRating, "0, 1, 2 or 3"));
        } else if (instrument == "tlx") {
            if (occasion != "after_condition" || condition.empty())
                row.bad(kOccasion, "after_condition, with the condition, for the TLX");
            const std::optional<int> item = tlxItemIndex(row.at(kItem));
            if (!item)
                row.bad(kItem,
                        "one of the TLX's subscales (mental, physical, temporal, performance, "
                        "effort, frustration)");
            const long long v = row.whole(kResponse, 0, kTlxMaxRating, "0 to 100 in steps of 5");
            if (v % kTlxStep != 0) row.bad(kResponse, "0 to 100 in steps of 5");
            tlx[condition][std::size_t(*item)] = int(v);
        } else if (instrument == "likert") {
            if (!isStudyName(row.at(kItem))) row.bad(kItem, "the item's id, " + std::string(kStudyNameRule));
            const long long v = row.whole(kResponse, 1, kMaxLikertRating, "a rating 1 to 11");
            // Asked after a condition: per condition; pre and post: once per session (post's
            // condition column names the last condition run, not a condition asked about).
            p.likert[{row.at(kItem), occasion, occasion == "after_condition" ? condition : ""}] = int(v);
        } else if (instrument == "text") {
            if (!isStudyName(row.at(kItem))) row.bad(kItem, "the item's id, " + std::string(kStudyNameRule));
        } else {
            row.bad(kInstrument, "ssq, tlx, likert or text");
        }
    }
    const auto complete = [](const auto& answers, auto& ratings) {
        for (std::size_t i = 0; i < answers.size(); ++i) {
            if (!answers[i]) return false;
            ratings[i] = *answers[i];
        }
        return true;
    };
    std::array<int, kSsqItemCount> ssq_ratings{};
    if (complete(ssq[0], ssq_ratings)) p.ssq_pre = scoreSsq(ssq_ratings);
    if (complete(ssq[1], ssq_ratings)) p.ssq_post = scoreSsq(ssq_ratings);
    for (const auto& [condition, answers] : tlx) {
        std::array<int, kTlxItemCount> ratings{};
        if (complete(answers, ratings)) p.tlx_raw[condition] = scoreTlxRaw(ratings);
    }
}

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
