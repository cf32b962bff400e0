// study/design.hpp: a within-subject study design (DESIGN.json, docs/study.md "Designs"),
// read strictly: named conditions (per-trial viewer settings), blocks of trials, practice
// trials, a minimum break between conditions, the participants, and how each participant's
// order of conditions is chosen (a balanced Latin square, every permutation in turn, or a
// seeded shuffle). expandSession() turns one participant's part of it into the list of
// trials that `ladarvr study` runs.
//
//   {"conditions": [{"name": "edl", "colour": "height", "eye_dome": true,
//                    "candidates": true, "time_limit_s": 60}, ...],
//    "blocks": [{"name": "easy", "trials": [<plan trials>]}, ...],
//    "practice": [<plan trials>], "break_s": 60,
//    "order": "latin" | "permutation" | "random", "seed": 1,
//    "participants": ["P01", "P02", ...],
//    "hit_radius_m": 1.0, "orbit": {...}, "generate": {...},     (as in a plan)
//    "questionnaires": {"ssq": true, "tlx": true,
//                       "likert": [{"id": "confident", "statement": "...", "points": 7,
//                                   "when": "after_condition"}],
//                       "text": [{"id": "remarks", "question": "...", "when": "post"}]}}
#pragma once
#include <study/plan.hpp>

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace study {

/// A named set of viewer settings that every trial of the condition runs with; an unset
/// field leaves the run's own setting (the command line's, or the trial's).
struct Condition {
    std::string name;
    std::optional<viewer::ColourMode> colour;
    std::optional<bool> eye_dome;
    bool candidates = true;                 // false: the trials' candidate boxes are not shown
    std::optional<double> time_limit_s;     // overrides every trial's own limit
    std::optional<viewer::ViewMode> start;  // the mode each trial starts in (automatic: the paper's)
    // The candidates come from this detector run on each trial's cloud instead of the
    // trial's file: "baseline" (the clustering detector) or a model file of `ladarvr train`.
    std::string detector;                // empty: the trials' own candidates
    std::optional<unsigned> tools;       // viewer::TrialTool bits offered; unset: every tool
    std::optional<bool> cut;             // the cutting volume on (or off) at each trial's start
    std::optional<double> cut_radius_m;  // its radius
};

struct DesignBlock {
    std::string name;  // default "1", "2", ... (its number)
    std::vector<PlanTrial> trials;
    // Or a selection from a corpus by difficulty, which readDesign turns into trials: the
    // corpus folder, the manifest condition (as `corpus --select`), how many items, the
    // shuffle's seed and each trial's time limit.
    std::filesystem::path corpus;
    std::string select;
    std::size_t count = 0;
    std::uint64_t select_seed = 1;
    double time_limit_s = 120.0;
};

enum class ConditionOrder { Latin, Permutation, Random };

/// When a questionnaire item is asked: before the session's first trial, after its last,
/// or after each condition's last trial.
enum class QuestionWhen { Pre, Post, AfterCondition };
/// "pre", "post", "after_condition" (questionnaires.csv's `occasion`).
const char* questionWhenName(QuestionWhen when);

/// A Likert item: `statement` rated 1 to `points`.
struct LikertItem {
    std::string id;  // the `item` column; a name as for conditions
    std::string statement;
    int points = 7;  // 2..11
    QuestionWhen when = QuestionWhen::Post;
};

/// A free-text question: answered on the desktop only (a headset has no keyboard).
struct TextItem {
    std::string id;
    std::string question;
    QuestionWhen when = QuestionWhen::Post;
};

/// The questionnaires a session asks (study/instruments.hpp has the standard ones).
struct Questionnaires {
    bool ssq = false;  // the SSQ before the first trial and after the last
    bool tlx = false;  // the raw NASA-TLX after each condition's last trial
    std::vector<LikertItem> likert;
    std::vector<TextItem> text;
    bool any() const { return ssq || tlx || !likert.empty() || !text.empty(); }
};

/// Bounds on the design's own questionnaire items.
inline constexpr std::size_t kMaxQuestionItems = 100;
inline constexpr std::size_t kMaxStatementChars = 300;

struct Design {
    std::vector<Condition> conditions;
    std::vector<DesignBlock> blocks;
    std::vector<PlanTrial> practice;  // run before each condition's blocks, not analysed
    double break_s = 0.0;             // minimum rest between two conditions
    ConditionOrder order = ConditionOrder::Latin;
    std::uint64_t seed = 0;  // ConditionOrder::Random only
    std::vector<std::string> participants;
    Plan settings;                  // hit radius, orbit and generate settings (its trials empty)
    Questionnaires questionnaires;  // none unless the design asks for them
};

/// The largest design read, and bounds on its lists.
inline constexpr std::size_t kMaxDesignBytes = std::size_t(1) << 20;
inline constexpr std::size_t kMaxConditions = 26;
inline constexpr std::size_t kMaxPermutationConditions = 8;  // 8! = 40320 orders
inline constexpr std::size_t kMaxParticipants = 10000;

/// Whether `s` may name a condition, a block, a questionnaire item or a participant:
/// kStudyNameRule. Such names are written into study.json and the CSV files as they are
/// (never starting with '-', no cell of them reads as a formula in a spreadsheet) and are
/// checked again wherever a session's files are read back.
bool isStudyName(std::string_view s);
inline constexpr std::string_view kStudyNameRule = "1 to 40 letters, digits, '_', '-' or '.', not starting with '-'";

/// A study file is a design when its top level is an object with a `conditions` key (a
/// plan has `trials` instead). Text that is not strict JSON (study/plan.hpp's rules) is
/// neither: throws core::Error("study: <name>: ...") naming what is wrong, so that is what
/// the user reads rather than a guess at the file's kind.
bool isDesignText(std::string_view text, const std::string& name);

/// Parses design text; relative paths are taken from `base`. Throws core::Error("study:
/// <name>: conditions[1].colour 'hue' is not one of file, height, white, label,
/// above-ground") naming the key and what is allowed; unknown keys are refused.
Design parseDesign(std::string_view text, const std::string& name, const std::filesystem::path& base);
/// Reads a design file (regular file, at most kMaxDesignBytes), checks every file it
/// names, and returns it with `sha256` set to the file's SHA-256 (hex).
Design readDesign(const std::filesystem::path& file, std::string* sha256 = nullptr);

/// The rows of the balanced Latin square for n conditions (Williams 1949): row r is the
/// first row 0, 1, n-1, 2, n-2, ... plus r (mod n). For an even n its n rows have each
/// condition once in each position and each ordered pair of conditions adjacent once;
/// for an odd n the n rows are followed by their reverses (2n rows) for the same balance.
std::vector<std::vector<int>> williamsSquare(int n);

/// The order of conditions (indices into design.conditions) for the participant at
/// `participant_index` in design.participants: Latin, row index mod the square's rows;
/// Permutation, the index mod n!-th permutation in lexicographic order; Random, a
/// shuffle seeded by the design's seed and the index (the same on every machine).
std::vector<int> conditionOrder(const Design& design, std::size_t participant_index);

/// Where a session trial comes from.
struct SessionTrial {
    int condition = 0;  // index into design.conditions
    int block = 0;      // index into design.blocks; -1 for a practice trial
    bool practice = false;
};

/// One participant's session: the trials in the order they run, each with its
/// condition's settings applied (a plan whose trials run in its own order).
struct Session {
    std::string participant;
    std::vector<int> condition_order;
    Plan plan;
    std::vector<SessionTrial> trials;  // parallel to plan.trials
};

/// Expands `participant`'s session: for each condition in its order, the practice trials
/// then every block's trials; the first trial of every condition but the first carries
/// the break. Throws core::Error("study: --participant 'P99' is not in <name>'s
/// participants (P01, ..., P12)").
Session expandSession(const Design& design, const std::string& participant, const std::string& name);

}  // namespace study
