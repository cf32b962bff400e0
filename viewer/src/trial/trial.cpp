// viewer/src/trial/trial.cpp: names of the study's decisions and verdicts (the words in its CSV files).
#include <viewer/trial.hpp>

namespace viewer {

const char* decisionName(Decision d) {
    switch (d) {
        case Decision::Confirm: return "confirm";
        case Decision::NoTarget: return "no_target";
        case Decision::Timeout: return "timeout";
        case Decision::Quit: return "quit";
    }
    return "?";
}

const char* verdictName(Verdict v) {
    switch (v) {
        case Verdict::Unreviewed: return "unreviewed";
        case Verdict::Confirmed: return "confirmed";
        case Verdict::Rejected: return "rejected";
    }
    return "?";
}

}  // namespace viewer
