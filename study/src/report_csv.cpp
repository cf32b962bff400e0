// study/src/report_csv.cpp: the study report's CSV inputs (study/report.hpp): a design
// session's trials.csv and questionnaires.csv, parsed from text (RFC 4180) and checked
// field by field, so a report never stands on a malformed row. report_read.cpp finds the
// folders and reads the files; the text alone is parsed here, which needs no file system.
#include <study/report.hpp>

#include <study/design.hpp>
#include <study/instruments.hpp>
#include <study/study_log.hpp>

#include <core/error.hpp>

#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <map>
#include <optional>
#include <set>

namespace study {

namespace {
constexpr std::string_view kQuestionnairesHeader = "participant,condition,instrument,occasion,item,response,time_s";

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

// Record `rec` as a row of the file whose header gave `columns`: as many fields, or one line.
RowReader rowOf(const std::string& file, const CsvRecord& rec, const std::vector<std::string>& columns) {
    if (rec.fields.size() != columns.size())
        throw core::Error(file + ": line " + std::to_string(rec.line) + ": " + std::to_string(rec.fields.size()) +
                          " fields; allowed: " + std::to_string(columns.size()) + ", as the header");
    return RowReader{file, rec, columns};
}

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
        const RowReader row = rowOf(file, rec, columns);
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
        const RowReader row = rowOf(file, rec, columns);
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
        } else if (instrument == "likert" || instrument == "text") {
            // Asked after a condition: the session writes which one; without it the answer
            // would become a figure of no condition.
            if (occasion == "after_condition" && condition.empty())
                row.bad(kCondition, "the condition, with occasion after_condition");
            if (!isStudyName(row.at(kItem))) row.bad(kItem, "the item's id, " + std::string(kStudyNameRule));
            if (instrument == "likert") {
                const long long v = row.whole(kResponse, 1, kMaxLikertRating, "a rating 1 to 11");
                // Asked after a condition: per condition; pre and post: once per session (post's
                // condition column names the last condition run, not a condition asked about).
                p.likert[{row.at(kItem), occasion, occasion == "after_condition" ? condition : ""}] = int(v);
            }
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

}  // namespace study
