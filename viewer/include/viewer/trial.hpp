// viewer/trial.hpp: target validation in the viewer: a study's trials, what the operator
// decides, and what the viewer reports for the study's log.
//
// The viewer runs trials one after another in one window and one XR session. Each trial
// opens on a ready screen that the operator dismisses (trigger / Enter / script `next`),
// then starts in automatic mode (the paper's protocol). It ends on confirm, no_target, its
// time limit, or quit (Escape, window closed, SIGINT/SIGTERM: the remaining trials are not
// run). Frame numbers of a --script count from the start of the run, not of the trial.
//
// Files the study runner writes from these reports (docs/study.md explains every column):
//   trials.csv: trial, cloud, decision, designated_x, designated_y, designated_z,
//     target_distance_m, hit, time_to_first_designation_s, time_to_decision_s,
//     designations, mode_switches, seconds_in_free_mode, visibility_metric (a design's
//     session adds participant, condition, block, practice), name, candidates_shown,
//     designation_hit, box_hit
//   candidates.csv: trial, candidate, score, verdict, t_s
//   trace_<trial>.csv: t_s, head_x, head_y, head_z, head_qw, head_qx, head_qy, head_qz,
//     mode, scale, hit_x, hit_y, hit_z   (world coordinates; hit_* empty without a hit)
#pragma once
#include <core/candidates.hpp>
#include <viewer/mode_controller.hpp>

#include <glm/gtc/quaternion.hpp>
#include <glm/vec3.hpp>

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace io {
struct TraceRow;
}

namespace viewer {

class CloudFeed;
class TerrainFeed;      // viewer/terrain_feed.hpp
enum class ColourMode;  // viewer/viewer.hpp

enum class Decision { Confirm, NoTarget, Timeout, Quit };
enum class Verdict { Unreviewed, Confirmed, Rejected };
/// "confirm", "no_target", "timeout", "quit".
const char* decisionName(Decision d);
/// "unreviewed", "confirmed", "rejected".
const char* verdictName(Verdict v);

/// One frame of the operator's trace, world coordinates, double precision.
struct TraceSample {
    double t_s = 0.0;            // since the ready screen was dismissed
    glm::dvec3 head_world{0.0};  // between the eyes
    glm::dquat head_orientation{1, 0, 0, 0};
    ViewMode mode = ViewMode::Automatic;
    double scale = 1.0;                   // world scale of the zoom (1 = life size)
    std::optional<glm::dvec3> hit_world;  // where the pointer meets the cloud
};

/// A sample as a row of a trace file (io/trace_file.hpp: what a study records), and a row
/// as the sample a replay plays.
io::TraceRow toTraceRow(const TraceSample& sample);
TraceSample toTraceSample(const io::TraceRow& row);

/// How a trial ended.
struct TrialOutcome {
    Decision decision = Decision::Quit;
    std::optional<glm::dvec3> designated_world;  // the designation decided on
    std::optional<double> time_to_first_designation_s;
    double time_to_decision_s = 0.0;
    int designations = 0;
    int mode_switches = 0;
    double seconds_in_free_mode = 0.0;
    /// From the designated point to the nearest point of the cloud labelled target; empty
    /// without a designation or without target points.
    std::optional<double> target_distance_m;
    /// The cloud holds points labelled target (ground truth), so a hit can be judged.
    bool target_known = false;
    /// The centre of the bounds of the cloud's points labelled target, world coordinates;
    /// none without target points. A confirmed candidate box holding it holds the target.
    std::optional<glm::dvec3> target_centre_world;
    /// The terrain the trial's above-ground colours were drawn with (ViewTerrain::source),
    /// or why none came (the feed's failure); both empty when it had no terrain coming or
    /// ended before it came.
    std::string terrain_source, terrain_failure;
};

/// A mark the operator made during a trial, as a replay shows it again at its time: a
/// designation (`candidate` empty: the point, or none when the designation was withdrawn)
/// or a candidate's verdict.
struct TrialMark {
    double t_s = 0.0;  // since the ready screen was dismissed
    std::optional<glm::dvec3> designated_world;
    std::string candidate;  // the candidate's id, for a verdict
    Verdict verdict = Verdict::Unreviewed;
};

/// What a trial shows besides its cloud.
struct TrialSetup {
    std::string name;  // shown on the ready screen
    std::vector<core::Candidate> candidates;
    double time_limit_s = 0.0;  // 0: none
    /// The ready screen cannot be dismissed before it has been up this long (a break
    /// between a study's conditions); 0: as soon as the cloud is ready.
    double min_ready_s = 0.0;
    /// Per-trial display settings (a study's condition); unset: the run's, as they stand.
    std::optional<ColourMode> colour;
    std::optional<bool> eye_dome;
    /// The mode the trial starts in once its ready screen is dismissed (unset: automatic,
    /// the paper's protocol). Starting free is logged as a switch from the condition, not
    /// counted among the operator's switches.
    std::optional<ViewMode> start_mode;
    /// The operator's tools this trial offers (TrialTool bits); unset: every one. The
    /// pointer, designation and decisions are always there.
    std::optional<unsigned> tools;
    /// The cutting volume on or off when the trial starts (on: it cuts once a point is
    /// designated, and stays on even where the trial leaves the cut tool out), and its
    /// radius; unset: the run's (--cut, --cut-radius).
    std::optional<bool> cut;
    std::optional<double> cut_radius_m;
    /// The ground under the trial's cloud for above-ground colours (viewer/terrain_feed.hpp),
    /// published by a producer the source stops at end(); the ready screen waits for it
    /// while the trial's colours are above-ground. Null: the run's (ViewerOptions::terrain).
    std::shared_ptr<TerrainFeed> terrain;
};

/// The tools a trial may leave out (TrialSetup::tools): the world zoom (grab scale), the
/// cutting volume, and cycling the colour mode.
enum TrialTool : unsigned { kToolZoom = 1u, kToolCut = 2u, kToolColour = 4u };
inline constexpr unsigned kAllTrialTools = kToolZoom | kToolCut | kToolColour;

/// A questionnaire item shown between trials (a study's questionnaires): a rating from
/// `min` to `max` in steps of `step`, or, `free_text`, a line of text typed on the
/// desktop (a headset has no keyboard: the item is skipped there).
struct Question {
    std::string title;  // the questionnaire ("Simulator sickness, before the session")
    std::string text;   // the item
    int min = 0, max = 3, step = 1;
    std::vector<std::string> labels;    // one per rating from min, or empty (the numbers)
    std::string low_label, high_label;  // under the scale's ends, or empty
    bool free_text = false;
    int number = 1, count = 1;  // item `number` of `count` of its questionnaire
};

/// How a question was answered: a rating's number or a text item's text; `skipped`: a
/// text item in the headset (response empty).
struct Answer {
    std::string response;
    bool skipped = false;
};

/// Supplies the trials, one at a time.
class TrialSource {
  public:
    virtual ~TrialSource() = default;
    virtual int count() const = 0;
    /// Trials of the study that ran before this run (a resumed session): the ready screen
    /// and the progress lines number trial k as numberOffset() + k + 1 of
    /// numberOffset() + count(). The observer and the run log still count from 0.
    virtual int numberOffset() const { return 0; }
    /// Starts producing trial `trial`'s cloud into `feed` (a fresh feed per trial; e.g.
    /// feed.startFileLoader, or a thread the source owns and joins) and returns its setup.
    virtual TrialSetup begin(int trial, CloudFeed& feed) = 0;
    /// Called before trial `trial`'s feed is destroyed (at the next trial and at the end
    /// of the run): stop producing into it (join the thread that does).
    virtual void end(int /*trial*/) {}
    /// The questions asked at gap `gap` of this run (0..count()): gap 0 before its first
    /// trial, gap k after trial k - 1 ends and before trial k starts (0-based trials), gap
    /// count() after the last. A run with count() 0 asks only gap 0's.
    virtual std::vector<Question> questions(int /*gap*/) { return {}; }
};

/// Receives what happens during each trial, as it happens (the study runner writes its
/// files from these calls, so a crash loses at most the trial in flight).
class TrialObserver {
  public:
    virtual ~TrialObserver() = default;
    virtual void onStart(int /*trial*/) {}
    virtual void onFrame(int /*trial*/, const TraceSample& /*sample*/) {}
    virtual void onDesignate(int /*trial*/, double /*t_s*/, const glm::dvec3& /*point_world*/) {}
    /// The operator withdrew the standing designation (reject pointing at no box).
    virtual void onWithdraw(int /*trial*/, double /*t_s*/) {}
    virtual void onVerdict(int /*trial*/, double /*t_s*/, const core::Candidate& /*candidate*/, Verdict /*verdict*/) {}
    /// Called once per trial that started; candidates never reviewed are reported before it
    /// with Verdict::Unreviewed.
    virtual void onEnd(int /*trial*/, const TrialOutcome& /*outcome*/) {}
    /// Question `question` (an index into the source's questions(gap)) answered.
    virtual void onAnswer(int /*gap*/, int /*question*/, const Answer& /*answer*/) {}
};

}  // namespace viewer
