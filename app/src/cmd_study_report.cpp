// app/src/cmd_study_report.cpp: `ladarvr study report RESULTS... --out REPORT`
// (docs/study.md "The report"): the paths checked at the boundary (no output inside an
// input, nor an input inside the report folder), then study/report.hpp reads the session
// folders, a warning is printed for each session that is not complete, and the report
// folder is written.
#include "cli_common.hpp"
#include "commands.hpp"

#include <core/error.hpp>
#include <platform/output_folder.hpp>
#include <platform/safe_file.hpp>
#include <study/report.hpp>
#include <study/study_folder.hpp>

#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace app {

namespace {
struct ReportArgs {
    std::vector<std::string> results;
    std::string out;
};

// The names the report reads in a participant's session folder.
bool sessionFile(const std::string& name) { return study::isStudyFile(name) || name == "questionnaires.csv"; }

void runReport(const ReportArgs& a) {
    if (a.out.empty()) throw core::Error("study report: --out DIR is required (the report folder)");
    std::vector<platform::RunPath> paths{{"--out", a.out, platform::PathRole::OutputFolder, {}}};
    for (const std::string& r : a.results) {
        // A session folder is read by its files' names; a folder of sessions throughout.
        const bool session = study::isSessionFolder(r);
        paths.push_back({"RESULTS", r, platform::PathRole::InputFolder,
                         session ? platform::OwnedName(sessionFile) : platform::OwnedName{}});
    }
    platform::checkDistinctPaths("study report", paths);
    platform::checkOutputFolder(a.out, study::isReportFile);
    std::vector<std::filesystem::path> given(a.results.begin(), a.results.end());
    const study::StudyResults results = study::readStudyResults(study::findSessionFolders(given));
    for (const std::string& w : study::sessionWarnings(results)) warn(w);
    study::writeStudyReport(results, a.out);
    std::fprintf(stderr,
                 "study report: %zu participant(s), %zu condition(s); sessions: %zu complete, %zu partial, %zu empty; "
                 "wrote %s/index.html\n",
                 results.participants.size(), results.conditions.size(),
                 study::countSessions(results, study::SessionState::Complete),
                 study::countSessions(results, study::SessionState::Partial),
                 study::countSessions(results, study::SessionState::Empty),
                 platform::printableUtf8(a.out, 400).c_str());
}
}  // namespace

CLI::App* registerStudyReport(CLI::App& study) {
    auto args = std::make_shared<ReportArgs>();
    CLI::App* cmd = study.add_subcommand(
        "report",
        "merge participants' session folders of one design into a report: figures per condition and "
        "participant, confidence intervals, within-subject tests, plots, index.html (docs/study.md)");
    cmd->add_option("results", args->results,
                    "a participant's session folder (its --out), or a folder whose sub-folders are sessions")
        ->required();
    cmd->add_option("--out", args->out, "the report folder (new, empty, or an earlier report: replaced whole)")
        ->required();
    cmd->callback([args] { runReport(*args); });
    return cmd;
}

}  // namespace app
