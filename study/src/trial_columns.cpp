// study/src/trial_columns.cpp: trials.csv's header (study/study_log.hpp), in each of its
// column sets: the log writes it and the report (report_csv.cpp) reads it back. Apart from
// study_log.cpp so that a reader of the file needs none of the log's writing.
#include <study/study_log.hpp>

#include <string>

namespace study {

namespace {
constexpr const char* kTrialColumns =
    "trial,cloud,decision,designated_x,designated_y,designated_z,target_distance_m,hit,"
    "time_to_first_designation_s,time_to_decision_s,designations,mode_switches,seconds_in_free_mode,"
    "visibility_metric";
constexpr const char* kDesignColumns = ",participant,condition,block,practice";
constexpr const char* kNameColumns = ",name,candidates_shown";
constexpr const char* kJudgedColumns = ",designation_hit,box_hit";
std::string laterColumns(TrialColumns columns) {
    return std::string(columns >= TrialColumns::Named ? kNameColumns : "") +
           (columns >= TrialColumns::Judged ? kJudgedColumns : "");
}
}  // namespace

std::string StudyLog::trialsHeader(TrialColumns columns) { return std::string(kTrialColumns) + laterColumns(columns); }
std::string StudyLog::designTrialsHeader(TrialColumns columns) {
    return std::string(kTrialColumns) + kDesignColumns + laterColumns(columns);
}

}  // namespace study
