// study/src/study_folder.cpp: the study's output folder and study.json (study/study_folder.hpp).
#include <study/study_folder.hpp>

#include <core/error.hpp>
#include <io/strict_json.hpp>
#include <platform/atomic_file.hpp>
#include <platform/safe_file.hpp>

#include <charconv>
#include <system_error>

#include <sys/stat.h>

namespace study {

std::string traceFileName(int trial_number) { return "trace_" + std::to_string(trial_number) + ".csv"; }

bool isStudyFile(std::string_view name) {
    return name == "trials.csv" || name == "candidates.csv" || name == "questionnaires.csv" || name == "study.json" ||
           (name.starts_with("trace_") && name.ends_with(".csv")) ||
           (name.starts_with("shown_") && name.ends_with(".json"));
}

void checkStudyFolder(const std::filesystem::path& out) {
    std::error_code ec;
    if (!std::filesystem::is_directory(out, ec)) throw core::Error("study: --out " + out.string() + ": not a folder");
    for (const auto& entry : std::filesystem::directory_iterator(out, ec)) {
        const std::string name = entry.path().filename().string();
        if (isStudyFile(name))
            throw core::Error("study: --out " + out.string() + ": already holds a study (" + name +
                              "); allowed: a new or empty folder");
    }
}

void writeStudyRecord(const std::filesystem::path& dir, const std::filesystem::path& plan_file,
                      const std::vector<int>& order) {
    platform::writeFileAtomic(
        dir / "study.json",
        nlohmann::json{{"plan", std::filesystem::absolute(plan_file).string()}, {"order", order}}.dump(2) + "\n");
}

void writeDesignRecord(const std::filesystem::path& dir, const std::filesystem::path& design_file,
                       const std::string& design_sha256, const std::vector<std::string>& condition_names,
                       const Session& session) {
    std::vector<std::string> names;
    for (int c : session.condition_order) names.push_back(condition_names[static_cast<std::size_t>(c)]);
    std::vector<int> order(session.plan.trials.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
    platform::writeFileAtomic(dir / "study.json",
                              nlohmann::json{{"design", std::filesystem::absolute(design_file).string()},
                                             {"design_sha256", design_sha256},
                                             {"participant", session.participant},
                                             {"condition_order", names},
                                             {"order", order}}
                                      .dump(2) +
                                  "\n");
}

RecordedStudy readStudyRecord(const std::filesystem::path& dir, const std::string& what) {
    const std::string shown = core::printable((dir / "study.json").string(), 400);
    const std::string where = what + " " + shown;
    const nlohmann::json study =
        io::parseStrictJson(platform::readTextFile(dir / "study.json", std::size_t(1) << 20, where + ":"), where);
    const bool design = study.is_object() && study.contains("design");
    if (design && (!study["design"].is_string() || !study.contains("design_sha256") ||
                   !study["design_sha256"].is_string() || !study.contains("participant") ||
                   !study["participant"].is_string() || !study.contains("order") || !study["order"].is_array()))
        throw core::Error(
            where + ": not a design session's record (needs 'design', 'design_sha256', 'participant' and 'order')");
    if (!design && (!study.is_object() || !study.contains("plan") || !study["plan"].is_string() ||
                    !study.contains("order") || !study["order"].is_array()))
        throw core::Error(where + ": not a study's record (needs 'plan' and 'order')");
    RecordedStudy record;
    if (design) {
        if (!isStudyName(study["participant"].get<std::string>()))
            throw core::Error(where + ": participant is not an id of " + std::string(kStudyNameRule));
        const std::string file = study["design"].get<std::string>();
        std::string sha;
        const Design d = readDesign(file, &sha);
        if (sha != study["design_sha256"].get<std::string>())
            throw core::Error(where + ": the design " + core::printable(file, 400) +
                              " changed since the run (its SHA-256 differs); allowed: the design as it was run");
        record.plan = expandSession(d, study["participant"].get<std::string>(), core::printable(file, 400)).plan;
    } else {
        record.plan = readPlan(study["plan"].get<std::string>());
    }
    for (const auto& v : study["order"]) {
        if (!v.is_number_unsigned() || v.get<std::size_t>() >= record.plan.trials.size())
            throw core::Error(where + ": 'order' does not match the plan's trials");
        record.order.push_back(v.get<int>());
    }
    return record;
}

std::optional<RecordedTrial> recordedTraceTrial(const std::filesystem::path& trace, const std::string& what) {
    const std::string name = trace.filename().string();
    if (!isStudyFile(name) || !name.starts_with("trace_")) return std::nullopt;
    const std::string digits = name.substr(6, name.size() - 6 - 4);
    int number = 0;
    const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), number);
    // Only the name the study writes (traceFileName): no sign, no leading zero.
    if (ec != std::errc() || end != digits.data() + digits.size() || number < 1 || traceFileName(number) != name)
        return std::nullopt;
    const std::filesystem::path folder = trace.parent_path().empty() ? std::filesystem::path(".") : trace.parent_path();
    struct stat st{};
    if (::lstat((folder / "study.json").c_str(), &st) != 0) return std::nullopt;
    RecordedStudy study = readStudyRecord(folder, what);
    if (static_cast<std::size_t>(number) > study.order.size())
        throw core::Error(what + " " + core::printable(trace.string(), 400) + ": " +
                          core::printable((folder / "study.json").string(), 400) + " records " +
                          std::to_string(study.order.size()) + " trials, not trial " + std::to_string(number) +
                          "; allowed the trace of one of its trials");
    RecordedTrial recorded;
    recorded.number = number;
    recorded.folder = folder;
    recorded.trial = std::move(study.plan.trials[static_cast<std::size_t>(study.order[std::size_t(number - 1)])]);
    return recorded;
}

}  // namespace study
