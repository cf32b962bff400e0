// study/src/questionnaire.cpp: a session's questionnaire schedule and questionnaires.csv's
// rows (study/questionnaire.hpp).
#include <study/questionnaire.hpp>

#include <study/csv_cell.hpp>
#include <study/instruments.hpp>

#include <cstdio>

namespace study {

const char* instrumentName(Instrument instrument) {
    switch (instrument) {
        case Instrument::Ssq: return "ssq";
        case Instrument::Tlx: return "tlx";
        case Instrument::Likert: return "likert";
        case Instrument::Text: return "text";
    }
    return "?";
}

namespace {
// Appends the questions of one occasion at `gap`: the SSQ or TLX when asked, then the
// design's Likert and text items for that occasion.
void addOccasion(std::vector<ScheduledQuestion>& out, const Design& design, std::size_t gap, QuestionWhen when,
                 const std::string& condition) {
    const Questionnaires& q = design.questionnaires;
    auto add = [&](Instrument instrument, std::string item, std::string text, int min, int max, int step) {
        ScheduledQuestion s;
        s.gap = gap;
        s.instrument = instrument;
        s.when = when;
        s.condition = condition;
        s.item = std::move(item);
        s.text = std::move(text);
        s.min = min;
        s.max = max;
        s.step = step;
        out.push_back(std::move(s));
    };
    auto numberRun = [&](std::size_t first) {  // item k of n within one instrument's run
        for (std::size_t i = first; i < out.size(); ++i) {
            out[i].number = static_cast<int>(i - first + 1);
            out[i].count = static_cast<int>(out.size() - first);
        }
    };
    std::size_t first = out.size();
    if (q.ssq && when != QuestionWhen::AfterCondition) {
        for (const SsqItem& s : ssqItems())
            add(Instrument::Ssq, std::string(s.item.id), std::string(s.item.text), 0, kSsqMaxRating, 1);
        numberRun(first);
    }
    first = out.size();
    if (q.tlx && when == QuestionWhen::AfterCondition) {
        for (const InstrumentItem& t : tlxItems())
            add(Instrument::Tlx, std::string(t.id), std::string(t.text), 0, kTlxMaxRating, kTlxStep);
        numberRun(first);
    }
    first = out.size();
    for (const LikertItem& l : q.likert)
        if (l.when == when) add(Instrument::Likert, l.id, l.statement, 1, l.points, 1);
    numberRun(first);
    first = out.size();
    for (const TextItem& t : q.text)
        if (t.when == when) add(Instrument::Text, t.id, t.question, 0, 0, 1);
    numberRun(first);
}
}  // namespace

std::vector<ScheduledQuestion> questionSchedule(const Design& design, const Session& session) {
    std::vector<ScheduledQuestion> out;
    if (!design.questionnaires.any() || session.trials.empty()) return out;
    const std::size_t n = session.trials.size();
    addOccasion(out, design, 0, QuestionWhen::Pre, "");
    for (std::size_t i = 0; i < n; ++i) {
        const int c = session.trials[i].condition;
        const bool last_of_condition = i + 1 == n || session.trials[i + 1].condition != c;
        if (last_of_condition)
            addOccasion(out, design, i + 1, QuestionWhen::AfterCondition,
                        design.conditions[static_cast<std::size_t>(c)].name);
    }
    addOccasion(out, design, n, QuestionWhen::Post,
                design.conditions[static_cast<std::size_t>(session.trials.back().condition)].name);
    return out;
}

const char* questionnairesHeader() { return "participant,condition,instrument,occasion,item,response,time_s"; }

std::string questionnaireRow(const std::string& participant, const ScheduledQuestion& q, const std::string& response,
                             double time_s) {
    char time[64];
    std::snprintf(time, sizeof time, "%.6f", time_s);
    return csvCell(participant) + "," + csvCell(q.condition) + "," + csvCell(instrumentName(q.instrument)) + "," +
           csvCell(questionWhenName(q.when)) + "," + csvCell(q.item) + "," + csvCell(response) + "," + time;
}

}  // namespace study
