// study/src/study_log.cpp: trials.csv, candidates.csv and the per-trial traces.
#include <study/study_log.hpp>

#include <core/error.hpp>
#include <platform/atomic_file.hpp>
#include <platform/safe_file.hpp>

#include <cmath>
#include <sstream>

#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <unistd.h>

namespace study {

namespace {
std::string fixed(double v, int digits = 6) {
    char buffer[64];
    std::snprintf(buffer, sizeof buffer, "%.*f", digits, v);
    return buffer;
}
std::string optionalFixed(const std::optional<double>& v, int digits = 6) { return v ? fixed(*v, digits) : ""; }
}  // namespace

std::string csvText(const std::string& text) {
    if (text.find_first_of(",\"\r\n") == std::string::npos) return text;
    std::string out = "\"";
    for (char c : text) {
        if (c == '"') out += '"';
        out += c;
    }
    return out + "\"";
}

const char* StudyLog::trialsHeader() {
    return "trial,cloud,decision,designated_x,designated_y,designated_z,target_distance_m,hit,"
           "time_to_first_designation_s,time_to_decision_s,designations,mode_switches,seconds_in_free_mode,"
           "visibility_metric";
}
const char* StudyLog::candidatesHeader() { return "trial,candidate,score,verdict,t_s"; }
const char* StudyLog::traceHeader() {
    return "t_s,head_x,head_y,head_z,head_qw,head_qx,head_qy,head_qz,mode,scale,hit_x,hit_y,hit_z";
}

StudyLog::StudyLog(std::filesystem::path dir, std::function<TrialInfo(int)> info, double hit_radius_m)
    : dir_(std::move(dir)), info_(std::move(info)), hit_radius_m_(hit_radius_m) {}

StudyLog::~StudyLog() { closeTrace(); }

void StudyLog::writeAtomic(const std::string& name, const char* header, const std::vector<std::string>& rows) {
    std::string content = std::string(header) + "\n";
    for (const std::string& r : rows) content += r + "\n";
    try {
        platform::writeFileAtomic(dir_ / name, content);
    } catch (const std::exception& e) {
        if (error_.empty()) error_ = e.what();
    }
}

void StudyLog::closeTrace() {
    if (!trace_) return;
    if (std::fclose(trace_) != 0 && error_.empty())
        error_ = "output: " + trace_path_.string() + ": " + std::strerror(errno);
    trace_ = nullptr;
}

void StudyLog::onStart(int trial) {
    closeTrace();
    trace_path_ = dir_ / ("trace_" + std::to_string(trial + 1) + ".csv");
    // A new file only, never through a link: the folder is checked for earlier studies
    // before the run, so an existing name here is someone else's file.
    const int fd = ::open(trace_path_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
    if (fd < 0 || !(trace_ = ::fdopen(fd, "w"))) {
        if (fd >= 0) ::close(fd);
        if (error_.empty()) error_ = "output: " + trace_path_.string() + ": cannot create: " + std::strerror(errno);
        return;
    }
    std::fprintf(trace_, "%s\n", traceHeader());
}

void StudyLog::onFrame(int, const viewer::TraceSample& s) {
    if (!trace_) return;
    std::fprintf(trace_, "%.6f,%.6f,%.6f,%.6f,%.9f,%.9f,%.9f,%.9f,%s,%.9g,", s.t_s, s.head_world.x, s.head_world.y,
                 s.head_world.z, s.head_orientation.w, s.head_orientation.x, s.head_orientation.y,
                 s.head_orientation.z, viewer::modeName(s.mode), s.scale);
    if (s.hit_world) std::fprintf(trace_, "%.6f,%.6f,%.6f\n", s.hit_world->x, s.hit_world->y, s.hit_world->z);
    else std::fputs(",,\n", trace_);
}

void StudyLog::onVerdict(int trial, double t_s, const core::Candidate& candidate, viewer::Verdict verdict) {
    candidate_rows_.push_back(std::to_string(trial + 1) + "," + csvText(candidate.id) + "," + fixed(candidate.score) +
                              "," + viewer::verdictName(verdict) + "," + fixed(t_s));
}

void StudyLog::onEnd(int trial, const viewer::TrialOutcome& o) {
    closeTrace();
    const TrialInfo info = info_ ? info_(trial) : TrialInfo{};
    std::string row = std::to_string(trial + 1) + "," + csvText(info.source) + "," + viewer::decisionName(o.decision);
    for (int i = 0; i < 3; ++i) row += "," + (o.designated_world ? fixed((*o.designated_world)[i]) : std::string());
    row += "," + optionalFixed(o.target_distance_m);
    // hit: empty when the cloud has no ground truth (nothing to hit); else 1 only for a
    // confirmed point within the radius, 0 otherwise. A designation still standing at
    // no_target, timeout or quit was not the operator's answer: its distance is kept, its
    // hit is 0.
    if (o.target_known)
        row += (o.decision == viewer::Decision::Confirm && o.target_distance_m && *o.target_distance_m <= hit_radius_m_)
                   ? ",1"
                   : ",0";
    else
        row += ",";
    row += "," + optionalFixed(o.time_to_first_designation_s);
    row += "," + fixed(o.time_to_decision_s);
    row += "," + std::to_string(o.designations) + "," + std::to_string(o.mode_switches);
    row += "," + fixed(o.seconds_in_free_mode);
    row += "," + optionalFixed(info.visibility_metric);
    trial_rows_.push_back(std::move(row));
    writeAtomic("trials.csv", trialsHeader(), trial_rows_);
    writeAtomic("candidates.csv", candidatesHeader(), candidate_rows_);
}

std::vector<viewer::TraceSample> readTrace(const std::filesystem::path& file) {
    const std::string name = "study: " + core::printable(file.string(), 400);
    const std::string text = platform::readTextFile(file, std::size_t(512) << 20, name + ":");
    std::istringstream in(text);
    std::string line;
    std::vector<viewer::TraceSample> samples;
    if (!std::getline(in, line) || line != StudyLog::traceHeader())
        throw core::Error(name + " line 1: not a trace header; allowed: " + StudyLog::traceHeader());
    for (int number = 2; std::getline(in, line); ++number) {
        if (line.empty()) continue;
        std::vector<std::string> f;
        std::string field;
        std::istringstream ls(line);
        while (std::getline(ls, field, ',')) f.push_back(field);
        if (!line.empty() && line.back() == ',') f.push_back("");
        auto bad = [&](const std::string& what) { return core::Error(name + " line " + std::to_string(number) + ": " + what); };
        if (f.size() != 13) throw bad(std::to_string(f.size()) + " columns; allowed 13");
        auto num = [&](int i) {
            try {
                std::size_t used = 0;
                const double v = std::stod(f[std::size_t(i)], &used);
                if (used == f[std::size_t(i)].size() && std::isfinite(v)) return v;
            } catch (const std::exception&) {
            }
            throw bad("column " + std::to_string(i + 1) + " '" + core::printable(f[std::size_t(i)], 40) +
                      "' is not a finite number");
        };
        viewer::TraceSample s;
        s.t_s = num(0);
        s.head_world = {num(1), num(2), num(3)};
        s.head_orientation = glm::dquat(num(4), num(5), num(6), num(7));
        if (f[8] == "automatic") s.mode = viewer::ViewMode::Automatic;
        else if (f[8] == "free") s.mode = viewer::ViewMode::Free;
        else throw bad("mode '" + core::printable(f[8], 40) + "' is not one of automatic, free");
        s.scale = num(9);
        if (!(s.scale > 0.0)) throw bad("scale must be > 0");
        if (!f[10].empty() || !f[11].empty() || !f[12].empty()) s.hit_world = glm::dvec3(num(10), num(11), num(12));
        if (!samples.empty() && !(s.t_s > samples.back().t_s)) throw bad("t_s does not increase");
        samples.push_back(s);
    }
    return samples;
}

}  // namespace study
