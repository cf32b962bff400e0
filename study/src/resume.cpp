// study/src/resume.cpp: finding where a stopped design session resumes (study/resume.hpp).
#include <study/resume.hpp>

#include <study/csv_cell.hpp>
#include <study/questionnaire.hpp>
#include <study/study_folder.hpp>
#include <study/study_log.hpp>
#include <study/trial_shown.hpp>

#include <core/error.hpp>
#include <io/strict_json.hpp>
#include <platform/safe_file.hpp>

#include <cerrno>
#include <charconv>
#include <cstring>
#include <sys/stat.h>
#include <unistd.h>

namespace study {

namespace {
// The lines of a CSV file that the study wrote: '\n' separated, the last one ending in
// '\n' (the writer always ends its files so; no field holds a line break: csvCell
// writes one as an escape).
std::vector<std::string> lines(const std::string& text) {
    std::vector<std::string> out;
    std::size_t start = 0;
    while (start < text.size()) {
        const std::size_t end = text.find('\n', start);
        if (end == std::string::npos) {
            out.push_back(text.substr(start));
            break;
        }
        out.push_back(text.substr(start, end - start));
        start = end + 1;
    }
    return out;
}

// A hit column as the log writes one: 1, 0 or empty.
bool isFlag(const std::string& text) { return text.empty() || text == "0" || text == "1"; }
// A count as the log writes one: decimal digits, no sign, at most 9 of them.
bool isCount(const std::string& text) {
    return !text.empty() && text.size() <= 9 && text.find_first_not_of("0123456789") == std::string::npos;
}

bool nameExists(const std::filesystem::path& p) {
    struct stat st{};
    return ::lstat(p.c_str(), &st) == 0;
}
}  // namespace

std::vector<std::string> splitCsvLine(const std::string& line, const std::string& where) {
    std::vector<std::string> fields(1);
    bool quoted = false;
    for (std::size_t i = 0; i < line.size(); ++i) {
        const char c = line[i];
        if (quoted) {
            if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
                fields.back() += '"';
                ++i;
            } else if (c == '"') {
                quoted = false;
            } else {
                fields.back() += c;
            }
        } else if (c == '"' && fields.back().empty()) {
            quoted = true;
        } else if (c == ',') {
            fields.emplace_back();
        } else {
            fields.back() += c;
        }
    }
    if (quoted) throw core::Error(where + ": an unclosed quote");
    return fields;
}

std::optional<ResumePoint> findResumePoint(const std::filesystem::path& out, const std::string& design_sha256,
                                           const Design& design, const Session& session) {
    const std::string shown = core::printable(out.string(), 400);
    const std::string allowed = "; allowed: the same design and participant (to resume), or a new or empty folder";
    if (!nameExists(out / "study.json")) {
        checkStudyFolder(out);  // any other study file: refused as for a plan
        return std::nullopt;
    }
    const std::string where = "study: --out " + shown + "/study.json";
    const nlohmann::json record =
        io::parseStrictJson(platform::readOwnOutput(out / "study.json", std::size_t(1) << 20, where + ":"), where);
    if (!record.is_object() || !record.contains("design_sha256") || !record["design_sha256"].is_string() ||
        !record.contains("participant") || !record["participant"].is_string())
        throw core::Error("study: --out " + shown + " holds a study that is not a design's session" + allowed);
    if (record["design_sha256"].get<std::string>() != design_sha256)
        throw core::Error("study: --out " + shown + " holds a session of another design (SHA-256 " +
                          core::printable(record["design_sha256"].get<std::string>(), 64) + ")" + allowed);
    if (!isStudyName(record["participant"].get<std::string>()))
        throw core::Error("study: --out " + shown + "/study.json: participant is not an id of " +
                          std::string(kStudyNameRule) + allowed);
    if (record["participant"].get<std::string>() != session.participant)
        throw core::Error("study: --out " + shown + " holds participant " +
                          core::printable(record["participant"].get<std::string>(), 40) + "'s session" + allowed);

    ResumePoint point;
    const std::filesystem::path trials_file = out / "trials.csv";
    if (nameExists(trials_file)) {
        const std::string w = "study: --out " + core::printable(trials_file.string(), 400);
        const std::vector<std::string> rows = lines(platform::readOwnOutput(trials_file, kMaxResumeCsvBytes, w + ":"));
        // Sessions written before the later column sets came lack them, and go on so.
        std::optional<TrialColumns> layout;
        for (const TrialColumns c : {TrialColumns::Base, TrialColumns::Named, TrialColumns::Judged})
            if (!rows.empty() && rows[0] == StudyLog::designTrialsHeader(c)) layout = c;
        if (!layout) throw core::Error(w + ": line 1: not the header of a design session's trials.csv" + allowed);
        point.columns = *layout;
        const bool named = point.columns >= TrialColumns::Named;
        const std::size_t columns = point.columns == TrialColumns::Judged ? 22 : named ? 20 : 18;
        if (rows.size() - 1 > session.plan.trials.size())
            throw core::Error(w + ": " + std::to_string(rows.size() - 1) + " trials; this session has " +
                              std::to_string(session.plan.trials.size()) + allowed);
        for (std::size_t i = 1; i < rows.size(); ++i) {
            const std::string line_where = w + ": line " + std::to_string(i + 1);
            const std::vector<std::string> f = splitCsvLine(rows[i], line_where);
            const PlanTrial& t = session.plan.trials[i - 1];
            const SessionTrial& s = session.trials[i - 1];
            const std::string block = s.practice ? "" : design.blocks[static_cast<std::size_t>(s.block)].name;
            const std::string condition = design.conditions[static_cast<std::size_t>(s.condition)].name;
            // Text cells as csvCell wrote them (a cloud name may hold escapes or a leading ');
            // the design's columns are 14..17, name and candidates_shown 18 and 19, and
            // designation_hit and box_hit 20 and 21 (each 1, 0 or empty).
            const bool same = f.size() == columns && f[0] == std::to_string(i) && f[1] == csvSafeText(t.source) &&
                              f[14] == session.participant && f[15] == condition && f[16] == block &&
                              f[17] == (s.practice ? "1" : "0") &&
                              (!named || (f[18] == csvSafeText(t.name) && isCount(f[19]))) &&
                              (point.columns != TrialColumns::Judged || (isFlag(f[20]) && isFlag(f[21])));
            if (!same)
                throw core::Error(line_where + ": not trial " + std::to_string(i) + " of this session (" + t.source +
                                  ", condition " + condition + (s.practice ? ", practice" : ", block " + block) + ")" +
                                  allowed);
            point.trial_rows.push_back(rows[i]);
        }
    }
    point.trials_done = point.trial_rows.size();

    const std::filesystem::path candidates_file = out / "candidates.csv";
    if (nameExists(candidates_file)) {
        const std::string w = "study: --out " + core::printable(candidates_file.string(), 400);
        const std::vector<std::string> rows =
            lines(platform::readOwnOutput(candidates_file, kMaxResumeCsvBytes, w + ":"));
        if (rows.empty() || rows[0] != StudyLog::candidatesHeader())
            throw core::Error(w + ": line 1: not the header of a study's candidates.csv" + allowed);
        for (std::size_t i = 1; i < rows.size(); ++i) {
            const std::vector<std::string> f = splitCsvLine(rows[i], w + ": line " + std::to_string(i + 1));
            std::size_t trial = 0;
            const char* end = f[0].data() + f[0].size();
            const auto [ptr, ec] = std::from_chars(f[0].data(), end, trial);
            if (ec != std::errc() || ptr != end || trial == 0)
                throw core::Error(w + ": line " + std::to_string(i + 1) + ": trial '" + core::printable(f[0], 20) +
                                  "' is not a trial number");
            if (trial <= point.trials_done) point.candidate_rows.push_back(rows[i]);
        }
    } else if (point.trials_done > 0) {
        throw core::Error("study: --out " + shown + ": trials.csv has trials but candidates.csv is missing" + allowed);
    }

    // Questionnaires: the answers written are a prefix of the schedule, up to the gap the
    // session stopped in (the questions before the trial in progress, partly answered or
    // not), and hold every question of the gaps before it.
    const std::vector<ScheduledQuestion> schedule = questionSchedule(design, session);
    const std::filesystem::path questions_file = out / "questionnaires.csv";
    if (nameExists(questions_file)) {
        const std::string w = "study: --out " + core::printable(questions_file.string(), 400);
        const std::vector<std::string> rows =
            lines(platform::readOwnOutput(questions_file, kMaxQuestionnaireCsvBytes, w + ":"));
        if (rows.empty() || rows[0] != questionnairesHeader())
            throw core::Error(w + ": line 1: not the header of a session's questionnaires.csv" + allowed);
        for (std::size_t i = 1; i < rows.size(); ++i) {
            const std::string line_where = w + ": line " + std::to_string(i + 1);
            const std::vector<std::string> f = splitCsvLine(rows[i], line_where);
            if (i - 1 >= schedule.size() || schedule[i - 1].gap > point.trials_done)
                throw core::Error(line_where + ": an answer this session had not asked yet (after trial " +
                                  std::to_string(point.trials_done) + ")" + allowed);
            const ScheduledQuestion& q = schedule[i - 1];
            bool ok = f.size() == 7 && f[0] == session.participant && f[1] == q.condition &&
                      f[2] == instrumentName(q.instrument) && f[3] == questionWhenName(q.when) && f[4] == q.item;
            if (ok && q.instrument != Instrument::Text) {
                int v = 0;
                const char* end = f[5].data() + f[5].size();
                const auto [ptr, ec] = std::from_chars(f[5].data(), end, v);
                ok = ec == std::errc() && ptr == end && v >= q.min && v <= q.max && (v - q.min) % q.step == 0;
            }
            if (!ok)
                throw core::Error(line_where + ": not the answer to this session's question " + std::to_string(i) +
                                  " (" + instrumentName(q.instrument) + " " + q.item + ", " + questionWhenName(q.when) +
                                  (q.condition.empty() ? "" : ", condition " + q.condition) + ")" + allowed);
            point.questionnaire_rows.push_back(rows[i]);
        }
    }
    point.questions_answered = point.questionnaire_rows.size();
    for (std::size_t i = point.questions_answered; i < schedule.size(); ++i)
        if (schedule[i].gap < point.trials_done)
            throw core::Error("study: --out " + shown + ": questionnaires.csv lacks the answers asked before trial " +
                              std::to_string(schedule[i].gap + 1) + allowed);

    // The trace and shown file of the trial in progress (and of any later one) go: the
    // trial runs again.
    for (std::size_t n = point.trials_done + 1; n <= session.plan.trials.size(); ++n)
        for (const std::string& name : {traceFileName(static_cast<int>(n)), shownFileName(static_cast<int>(n))}) {
            const std::filesystem::path file = out / name;
            struct stat st{};
            if (::lstat(file.c_str(), &st) != 0) continue;
            if (!S_ISREG(st.st_mode))
                throw core::Error("study: --out " + core::printable(file.string(), 400) +
                                  ": not a regular file; allowed: the file a stopped session left");
            if (::unlink(file.c_str()) != 0)
                throw core::Error("study: --out " + core::printable(file.string(), 400) +
                                  ": cannot remove: " + std::strerror(errno));
        }
    return point;
}

}  // namespace study
