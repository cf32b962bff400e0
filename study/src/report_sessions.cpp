// study/src/report_sessions.cpp: how much of its session each folder of a study report
// recorded (study/report.hpp): complete, partial (fewer trials than study.json's `order`
// plans: its figures count the trials it has) or empty (no trial to count: left out), and
// the one warning per session that is not complete, so a report never counts a stopped
// session, or a folder holding only study.json, without saying so.
#include <study/report.hpp>

#include <core/error.hpp>

#include <algorithm>

namespace study {

SessionState sessionState(std::size_t recorded, std::size_t practice, std::size_t planned) {
    if (recorded <= practice) return SessionState::Empty;
    return recorded < planned ? SessionState::Partial : SessionState::Complete;
}

SessionRecord sessionRecord(const ParticipantResults& p) {
    SessionRecord s;
    s.folder = p.folder;
    s.participant = p.participant;
    s.trials_recorded = p.trials.size();
    s.trials_planned = p.trials_planned;
    s.practice_recorded =
        std::size_t(std::count_if(p.trials.begin(), p.trials.end(), [](const ReportTrial& t) { return t.practice; }));
    s.state = sessionState(s.trials_recorded, s.practice_recorded, s.trials_planned);
    return s;
}

std::string_view sessionStateName(SessionState s) {
    switch (s) {
        case SessionState::Complete: return "complete";
        case SessionState::Partial: return "partial";
        case SessionState::Empty: return "empty";
    }
    return "complete";
}

std::size_t countSessions(const StudyResults& results, SessionState s) {
    return std::size_t(std::count_if(results.sessions.begin(), results.sessions.end(),
                                     [s](const SessionRecord& r) { return r.state == s; }));
}

std::vector<std::string> sessionWarnings(const StudyResults& results) {
    std::vector<std::string> out;
    for (const SessionRecord& s : results.sessions) {
        if (s.state == SessionState::Complete) continue;
        const std::string where = "study report: " + core::printable(s.folder.string(), 400) + ": ";
        const std::string recorded = std::to_string(s.trials_recorded) + " of " + std::to_string(s.trials_planned) +
                                     " trial" + (s.trials_planned == 1 ? "" : "s") + " recorded";
        const std::size_t counted = s.trials_recorded - s.practice_recorded;
        if (s.trials_recorded == 0)
            out.push_back(where + "no trial recorded; left out");
        else if (s.state == SessionState::Empty)
            out.push_back(where + recorded + ", practice only; left out");
        else if (s.practice_recorded == 0)
            out.push_back(where + recorded + "; its figures count those " + std::to_string(counted));
        else
            out.push_back(where + recorded + " (" + std::to_string(s.practice_recorded) +
                          " practice); its figures count the other " + std::to_string(counted));
    }
    return out;
}

}  // namespace study
