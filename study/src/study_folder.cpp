// study/src/study_folder.cpp: the study's output folder and study.json (study/study_folder.hpp).
#include <study/study_folder.hpp>

#include <core/error.hpp>
#include <io/strict_json.hpp>
#include <platform/atomic_file.hpp>
#include <platform/safe_file.hpp>

#include <system_error>

namespace study {

std::string traceFileName(int trial_number) { return "trace_" + std::to_string(trial_number) + ".csv"; }

bool isStudyFile(std::string_view name) {
    return name == "trials.csv" || name == "candidates.csv" || name == "questionnaires.csv" || name == "study.json" ||
           (name.starts_with("trace_") && name.ends_with(".csv"));
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

RecordedStudy readStudyRecord(const std::filesystem::path& dir) {
    const std::string shown = core::printable((dir / "study.json").string(), 400);
    const nlohmann::json study = io::parseStrictJson(
        platform::readTextFile(dir / "study.json", std::size_t(1) << 20, "study: --replay " + shown + ":"),
        "study: --replay " + shown);
    const bool design = study.is_object() && study.contains("design");
    if (design && (!study["design"].is_string() || !study.contains("design_sha256") ||
                   !study["design_sha256"].is_string() || !study.contains("participant") ||
                   !study["participant"].is_string() || !study.contains("order") || !study["order"].is_array()))
        throw core::Error(
            "study: --replay " + shown +
            ": not a design session's record (needs 'design', 'design_sha256', 'participant' and 'order')");
    if (!design && (!study.is_object() || !study.contains("plan") || !study["plan"].is_string() ||
                    !study.contains("order") || !study["order"].is_array()))
        throw core::Error("study: --replay " + shown + ": not a study's record (needs 'plan' and 'order')");
    RecordedStudy record;
    if (design) {
        if (!isStudyName(study["participant"].get<std::string>()))
            throw core::Error("study: --replay " + shown + ": participant is not an id of " +
                              std::string(kStudyNameRule));
        const std::string file = study["design"].get<std::string>();
        std::string sha;
        const Design d = readDesign(file, &sha);
        if (sha != study["design_sha256"].get<std::string>())
            throw core::Error("study: --replay " + shown + ": the design " + core::printable(file, 400) +
                              " changed since the run (its SHA-256 differs); allowed: the design as it was run");
        record.plan = expandSession(d, study["participant"].get<std::string>(), core::printable(file, 400)).plan;
    } else {
        record.plan = readPlan(study["plan"].get<std::string>());
    }
    for (const auto& v : study["order"]) {
        if (!v.is_number_unsigned() || v.get<std::size_t>() >= record.plan.trials.size())
            throw core::Error("study: --replay " + shown + ": 'order' does not match the plan's trials");
        record.order.push_back(v.get<int>());
    }
    return record;
}

}  // namespace study
