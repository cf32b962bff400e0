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
    return name == "trials.csv" || name == "candidates.csv" || name == "study.json" ||
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

RecordedStudy readStudyRecord(const std::filesystem::path& dir) {
    const std::string shown = core::printable((dir / "study.json").string(), 400);
    const nlohmann::json study = io::parseStrictJson(
        platform::readTextFile(dir / "study.json", std::size_t(1) << 20, "study: --replay " + shown + ":"),
        "study: --replay " + shown);
    if (!study.is_object() || !study.contains("plan") || !study["plan"].is_string() || !study.contains("order") ||
        !study["order"].is_array())
        throw core::Error("study: --replay " + shown + ": not a study's record (needs 'plan' and 'order')");
    RecordedStudy record;
    record.plan = readPlan(study["plan"].get<std::string>());
    for (const auto& v : study["order"]) {
        if (!v.is_number_unsigned() || v.get<std::size_t>() >= record.plan.trials.size())
            throw core::Error("study: --replay " + shown + ": 'order' does not match the plan's trials");
        record.order.push_back(v.get<int>());
    }
    return record;
}

}  // namespace study
