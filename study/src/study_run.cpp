// study/src/study_run.cpp: a whole study run and the replay of a trial (study/study_run.hpp).
#include <study/study_run.hpp>

#include <study/instruments.hpp>
#include <study/questionnaire.hpp>
#include <study/scene_metric.hpp>
#include <study/study_folder.hpp>
#include <study/study_log.hpp>
#include <study/study_source.hpp>
#include <study/trial_shown.hpp>

#include <core/error.hpp>
#include <core/scene.hpp>
#include <io/scene_file.hpp>
#include <io/trace_file.hpp>
#include <platform/safe_file.hpp>
#include <viewer/cloud_feed.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <map>
#include <memory>
#include <optional>
#include <system_error>
#include <string>

namespace study {

namespace {
// The centre of each scene trial's target bounds, world coordinates (scenes without a
// target left out): a confirmed candidate box that holds it is a hit (StudyLog).
std::map<std::filesystem::path, glm::dvec3> sceneTargetCentres(const Plan& plan) {
    std::map<std::filesystem::path, glm::dvec3> centres;
    std::map<std::filesystem::path, bool> seen;
    for (const PlanTrial& t : plan.trials) {
        if (t.scene.empty() || seen[t.scene]) continue;
        seen[t.scene] = true;
        const core::Scene scene = io::loadScene(t.scene);
        const core::Bounds target = scene.bounds(core::RoleMask::of({core::Role::Target}));
        if (!target.empty()) centres[t.scene] = target.centre() + scene.origin;
    }
    return centres;
}

// How the questionnaire screen shows a scheduled question.
viewer::Question screenQuestion(const ScheduledQuestion& q) {
    viewer::Question v;
    v.text = q.text;
    v.min = q.min;
    v.max = q.max;
    v.step = q.step;
    v.number = q.number;
    v.count = q.count;
    const std::string when = q.when == QuestionWhen::Pre    ? "before the session"
                             : q.when == QuestionWhen::Post ? "after the session"
                                                            : "after this condition";
    switch (q.instrument) {
        case Instrument::Ssq:
            v.title = "Simulator sickness, " + when + ": how much does each symptom affect you right now?";
            v.labels = {"none", "slight", "moderate", "severe"};
            break;
        case Instrument::Tlx:
            v.title = "Workload of the condition just finished (NASA-TLX)";
            v.low_label = q.item == "performance" ? "perfect" : "very low";
            v.high_label = q.item == "performance" ? "failure" : "very high";
            break;
        case Instrument::Likert:
            v.title = "Questions, " + when;
            v.low_label = "1";
            v.high_label = std::to_string(q.max);
            break;
        case Instrument::Text:
            v.title = "Questions, " + when;
            v.free_text = true;
            break;
    }
    return v;
}
// The SSQ's scores of each occasion whose 16 answers are all in `rows` (questionnaires.csv's
// rows), one line each on stderr, for the experimenter at the end of a session.
void printSsqScores(const std::vector<std::string>& rows) {
    for (const char* occasion : {"pre", "post"}) {
        std::vector<int> ratings(std::size_t(kSsqItemCount), -1);
        for (const std::string& row : rows) {
            const std::vector<std::string> f = splitCsvLine(row, "questionnaires.csv");
            if (f.size() != 7 || f[2] != "ssq" || f[3] != occasion) continue;
            if (const auto i = ssqItemIndex(f[4])) ratings[std::size_t(*i)] = std::atoi(f[5].c_str());
        }
        if (std::find(ratings.begin(), ratings.end(), -1) != ratings.end()) continue;
        const SsqScores s = scoreSsq(ratings);
        std::fprintf(stderr, "ladarvr: study: SSQ %s: nausea %.2f, oculomotor %.2f, disorientation %.2f, total %.2f\n",
                     occasion, s.nausea, s.oculomotor, s.disorientation, s.total);
    }
}
}  // namespace

StudyRun::StudyRun(StudyOptions options) : options_(std::move(options)) {
    if (!options_.design.empty()) {
        design_ = readDesign(options_.design, &design_sha256_);
        session_ = expandSession(*design_, options_.participant, core::printable(options_.design.string(), 400));
        plan_ = session_.plan;
    } else {
        plan_ = readPlan(options_.plan);
    }
    if (options_.hit_radius_m) plan_.hit_radius_m = *options_.hit_radius_m;
    if (!(plan_.hit_radius_m > 0.0)) throw core::Error("study: --hit-radius must be > 0 m");
    viewer::ViewerOptions& o = options_.viewer;
    o.modes.orbit.radius_m = options_.orbit_radius_m.value_or(plan_.orbit_radius_m);
    o.modes.orbit.altitude_m = options_.orbit_height_m.value_or(plan_.orbit_height_m);
    o.modes.orbit_period_s = options_.orbit_period_s.value_or(plan_.orbit_period_s);
    if (!options_.script.empty()) o.script = viewer::readScript(options_.script);
    viewer::validate(o);
}

void StudyRun::checkFolder() {
    if (design_)
        resume_ = findResumePoint(options_.out, design_sha256_, *design_, session_);
    else
        checkStudyFolder(options_.out);
}

int StudyRun::run(std::chrono::steady_clock::time_point started) {
    const std::filesystem::path& out = options_.out;
    viewer::ViewerOptions o = options_.viewer;
    // A design's session runs in its own order (expandSession's); a plan's may be shuffled.
    std::vector<int> order = design_ ? std::vector<int>(plan_.trials.size()) : trialOrder(plan_);
    if (design_)
        for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
    const std::size_t done = resume_ ? resume_->trials_done : 0;
    // The questions still to ask, by gap of this run (gap g is the session's gap done + g).
    const std::vector<ScheduledQuestion> schedule =
        design_ ? questionSchedule(*design_, session_) : std::vector<ScheduledQuestion>{};
    const std::size_t answered = resume_ ? resume_->questions_answered : 0;
    std::vector<std::vector<ScheduledQuestion>> pending(order.size() - done + 1);
    for (std::size_t i = answered; i < schedule.size(); ++i) {
        // findResumePoint refuses a folder whose answers stop before the gap it resumes at.
        if (schedule[i].gap < done)
            throw core::Error("study: --out " + core::printable(out.string(), 400) +
                              ": questionnaires.csv lacks answers asked before trial " +
                              std::to_string(schedule[i].gap + 1));
        pending[schedule[i].gap - done].push_back(schedule[i]);
    }
    const bool questions_left = answered < schedule.size();
    if (resume_ && done < order.size())
        std::fprintf(stderr, "ladarvr: study: resuming participant %s's session at trial %zu of %zu\n",
                     session_.participant.c_str(), done + 1, order.size());
    else if (resume_ && questions_left)
        std::fprintf(stderr,
                     "ladarvr: study: resuming participant %s's session at its last questions (%zu of %zu answered)\n",
                     session_.participant.c_str(), answered, schedule.size());
    if (done == order.size() && !questions_left) {
        std::fprintf(stderr, "ladarvr: study: all %zu trials already written to %s\n", order.size(),
                     (out / "trials.csv").string().c_str());
        return 0;
    }
    auto source = std::make_unique<StudySource>(
        plan_, std::vector<int>(order.begin() + std::ptrdiff_t(done), order.end()), static_cast<int>(done));
    std::vector<std::vector<viewer::Question>> screens;
    for (const auto& gap : pending) {
        screens.emplace_back();
        for (const ScheduledQuestion& q : gap) screens.back().push_back(screenQuestion(q));
    }
    source->setQuestions(std::move(screens));
    source->setTerrain(options_.terrain, o.style.colour);
    // What --replay needs to find a trial's cloud again (a resumed session has it already).
    // Written before the window opens, so an unwritable folder fails first; a run that then
    // ends before its first trial starts or its first answer (a window that cannot open, a
    // first cloud that fails to load, Escape on the first ready screen) has recorded
    // nothing, and its study.json goes again: the folder is as it was, and the same command
    // runs there again.
    std::optional<StudyLog> log;
    struct RecordGuard {
        std::filesystem::path file;  // empty: nothing written by this run
        const std::optional<StudyLog>& log;
        ~RecordGuard() {
            std::error_code ec;
            if (!file.empty() && !(log && log->recordedAnything())) std::filesystem::remove(file, ec);
        }
    } record{{}, log};
    if (design_ && !resume_) {
        std::vector<std::string> names;
        for (const Condition& c : design_->conditions) names.push_back(c.name);
        writeDesignRecord(out, options_.design, design_sha256_, names, session_);
        record.file = out / "study.json";
    } else if (!design_) {
        writeStudyRecord(out, options_.plan, order);
        record.file = out / "study.json";
    }

    // The metric renders with its own EGL context: before the window opens.
    const std::map<std::filesystem::path, double> metrics =
        options_.metric ? sceneMetrics(plan_, o.modes.orbit.radius_m, o.modes.orbit.altitude_m)
                        : std::map<std::filesystem::path, double>{};
    const std::map<std::filesystem::path, glm::dvec3> target_centres = sceneTargetCentres(plan_);
    log.emplace(
        out,
        [&](int position) {
            const std::size_t k = static_cast<std::size_t>(order[static_cast<std::size_t>(position)]);
            const PlanTrial& t = plan_.trials[k];
            TrialInfo info;
            info.source = t.source;
            info.name = t.name;
            info.candidates_shown = static_cast<int>(source->candidatesOf(k).size());
            info.shown.candidates = source->candidatesOf(k);
            info.shown.colour = t.colour;
            info.shown.eye_dome = t.eye_dome;
            if (design_) {
                const SessionTrial& s = session_.trials[static_cast<std::size_t>(position)];
                info.participant = session_.participant;
                info.condition = design_->conditions[static_cast<std::size_t>(s.condition)].name;
                if (!s.practice) info.block = design_->blocks[static_cast<std::size_t>(s.block)].name;
                info.practice = s.practice;
            }
            if (const auto it = metrics.find(t.scene);
                !t.scene.empty() && it != metrics.end() && std::isfinite(it->second))
                info.visibility_metric = it->second;
            if (const auto it = target_centres.find(t.scene); !t.scene.empty() && it != target_centres.end())
                info.target_centre_world = it->second;
            return info;
        },
        plan_.hit_radius_m);
    if (design_) log->addDesignColumns();
    if (resume_) log->setColumns(resume_->columns);
    if (resume_) log->resumeAt(resume_->trials_done, resume_->trial_rows, resume_->candidate_rows);
    if (questions_left)
        log->setQuestions(session_.participant, std::move(pending),
                          resume_ ? resume_->questionnaire_rows : std::vector<std::string>{}, started);
    if (o.timeout_s > 0.0)
        o.timeout_s = std::max(
            0.001, o.timeout_s - std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count());
    int status = viewer::runTrials(o, *source, *log);
    if (!log->error().empty()) {
        std::fprintf(stderr, "ladarvr: study: %s\n", log->error().c_str());
        if (status == 0) status = 1;
    }
    std::fprintf(stderr, "ladarvr: study: %zu of %zu trials written to %s\n", log->trialsWritten(), plan_.trials.size(),
                 (out / "trials.csv").string().c_str());
    if (!record.file.empty() && !log->recordedAnything())
        std::fprintf(stderr, "ladarvr: study: no trial started: study.json removed, --out left as it was\n");
    if (questions_left) printSsqScores(log->questionRows());
    return status;
}

Replay::Replay(const std::filesystem::path& dir, int trial_number, viewer::ViewerOptions viewer)
    : options_(std::move(viewer)) {
    RecordedStudy recorded = readStudyRecord(dir);
    plan_ = std::move(recorded.plan);
    order_ = std::move(recorded.order);
    if (order_.empty())
        throw core::Error("study: --replay " + core::printable(dir.string(), 400) +
                          ": study.json's trial order is empty; allowed a study folder with at least one trial");
    if (trial_number < 1 || trial_number > static_cast<int>(order_.size()))
        throw core::Error("study: --trial " + std::to_string(trial_number) + ": allowed 1.." +
                          std::to_string(order_.size()));
    trial_ = trial_number - 1;
    options_.use_xr = false;
    const std::filesystem::path file = dir / traceFileName(trial_number);
    io::Trace trace = io::readTrace(file);
    if (!trace.study_columns)
        throw core::Error("trace: " + core::printable(file.string(), 400) +
                          ": line 1: no mode,scale,hit_x,hit_y,hit_z columns after "
                          "head_qz; allowed a study's trace (docs/study.md)");
    // The rows become samples in one allocation and are freed at once; the viewer plays the
    // samples where they are (viewer::ReplayPlayer borrows them).
    options_.replay.reserve(trace.rows.size());
    for (const io::TraceRow& row : trace.rows) options_.replay.push_back(viewer::toTraceSample(row));
    trace = io::Trace{};
    // What the trial showed and the operator's marks, as the study recorded them (a
    // study written before shown_<N>.json came has none: its replay shows no boxes).
    const std::filesystem::path shown_file = dir / shownFileName(trial_number);
    std::error_code ec;
    if (std::filesystem::symlink_status(shown_file, ec).type() != std::filesystem::file_type::not_found) {
        TrialShown shown = readTrialShown(shown_file);
        options_.candidates = std::move(shown.candidates);
        if (shown.colour) options_.style.colour = *shown.colour;
        if (shown.eye_dome) options_.style.eye_dome = *shown.eye_dome;
        options_.replay_marks = std::move(shown.marks);
    }
    viewer::validate(options_);
}

int Replay::run() {
    // The boxes come from the study folder: no candidates file is read, no detector runs.
    StudySource source(plan_, order_, 0, false);
    viewer::CloudFeed feed;
    feed.enableLodOrder();
    source.begin(trial_, feed);
    // The trial's ground, as the study built it, when it is replayed in above-ground colours.
    const std::filesystem::path& cloud = source.planTrial(trial_).cloud;
    CloudTerrain terrain;  // its job stops and joins before the feed goes
    if (start_terrain_ && !cloud.empty() && options_.style.colour == viewer::ColourMode::AboveGround) {
        terrain = start_terrain_(cloud);
        options_.terrain = terrain.feed;
    }
    int status = 1;
    try {
        status = viewer::runViewer(options_, feed);
    } catch (...) {
        source.end(trial_);
        throw;
    }
    source.end(trial_);
    return status;
}

}  // namespace study
