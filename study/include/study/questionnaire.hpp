// study/questionnaire.hpp: when a design's session asks its questionnaires
// (study/design.hpp's Questionnaires, study/instruments.hpp's items) and what each
// question is: the schedule that the session shows one item at a time, whose answers
// become the rows of questionnaires.csv (its layout: study/instruments.hpp).
//
// Questions sit in the gaps between trials: gap 0 comes before the session's first trial,
// gap k after trial k (1-based) ends and before trial k + 1 starts, gap N after the last
// of N trials. Gap 0 holds the `pre` items (SSQ, then Likert, then text, each in the
// design's order); the gap after a condition's last trial holds its `after_condition`
// items (TLX, then Likert, then text); the last gap then adds the `post` items (SSQ,
// Likert, text).
#pragma once
#include <study/design.hpp>

#include <cstddef>
#include <string>
#include <vector>

namespace study {

enum class Instrument { Ssq, Tlx, Likert, Text };
/// "ssq", "tlx", "likert", "text" (questionnaires.csv's `instrument`).
const char* instrumentName(Instrument instrument);

/// One question of a session.
struct ScheduledQuestion {
    std::size_t gap = 0;  // 0..trials (above)
    Instrument instrument = Instrument::Ssq;
    QuestionWhen when = QuestionWhen::Pre;
    std::string condition;           // the condition just run; empty for `pre`
    std::string item;                // the item's id
    std::string text;                // what the screen shows
    int min = 0, max = 3, step = 1;  // a rating's range (unused for text)
    int number = 1, count = 1;       // item `number` of `count` of its questionnaire at this gap
};

/// The session's questions in the order they are asked (by gap, then as above); empty
/// when the design asks none.
std::vector<ScheduledQuestion> questionSchedule(const Design& design, const Session& session);

/// questionnaires.csv's header line (without the line end).
const char* questionnairesHeader();

/// The row of questionnaires.csv for `q` answered `response` (a whole number, or a text
/// item's text) `time_s` seconds from the session's start.
std::string questionnaireRow(const std::string& participant, const ScheduledQuestion& q, const std::string& response,
                             double time_s);

/// The largest questionnaires.csv read back (a resumed session).
inline constexpr std::size_t kMaxQuestionnaireCsvBytes = std::size_t(16) << 20;
/// The longest free-text answer kept, in bytes.
inline constexpr std::size_t kMaxTextAnswerBytes = 1000;

}  // namespace study
