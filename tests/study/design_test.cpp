// tests/study/design_test.cpp: DESIGN.json parsing (known answers, refused keys), the
// balance of the Williams squares, the permutation and seeded random orders, and a
// participant's expanded session.
#include <study/design.hpp>

#include <core/error.hpp>

#include <test_files.hpp>
#include <test_paths.hpp>

#include <doctest/doctest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>

namespace {
std::string conditions(int n) {
    std::string s = "[";
    for (int i = 0; i < n; ++i) s += std::string(i ? "," : "") + R"({"name": "c)" + std::to_string(i) + R"("})";
    return s + "]";
}
std::string participants(int n) {
    std::string s = "[";
    for (int i = 0; i < n; ++i) s += std::string(i ? "," : "") + "\"P" + std::to_string(i + 1) + "\"";
    return s + "]";
}
study::Design design(int n, const std::string& order = "latin", const std::string& extra = "") {
    return study::parseDesign(R"({"conditions": )" + conditions(n) + R"(, "blocks": [{"trials": [{"cloud": "a.pcd"}]}],
        "participants": )" + participants(2 * n) +
                                  R"(, "order": ")" + order + "\"" + extra + "}",
                              "d.json", "/d");
}
}  // namespace

TEST_CASE("a design's conditions, blocks, practice, break and participants") {
    const study::Design d = study::parseDesign(R"({
        "conditions": [{"name": "edl", "colour": "height", "eye_dome": true, "time_limit_s": 60},
                       {"name": "plain", "eye_dome": false, "candidates": false, "start": "free"}],
        "blocks": [{"name": "easy", "trials": [{"cloud": "a.pcd", "candidates": "a.json"}, {"scene": "s.json"}]},
                   {"trials": [{"cloud": "b.pcd", "time_limit_s": 30}]}],
        "practice": [{"cloud": "p.pcd"}], "break_s": 45, "order": "latin",
        "participants": ["P01", "P02"], "hit_radius_m": 2, "generate": {"xres": 16}})",
                                               "d.json", "/d");
    REQUIRE(d.conditions.size() == 2);
    CHECK(d.conditions[0].name == "edl");
    CHECK(*d.conditions[0].colour == viewer::ColourMode::HeightJet);
    CHECK(*d.conditions[0].eye_dome);
    CHECK(d.conditions[0].candidates);
    CHECK(*d.conditions[0].time_limit_s == 60.0);
    CHECK_FALSE(d.conditions[1].colour);
    CHECK_FALSE(*d.conditions[1].eye_dome);
    CHECK_FALSE(d.conditions[1].candidates);
    CHECK_FALSE(d.conditions[1].time_limit_s);
    CHECK_FALSE(d.conditions[0].start);
    CHECK(*d.conditions[1].start == viewer::ViewMode::Free);
    CHECK(d.conditions[0].detector.empty());
    CHECK_FALSE(d.conditions[0].tools);
    REQUIRE(d.blocks.size() == 2);
    CHECK(d.blocks[0].name == "easy");
    CHECK(d.blocks[1].name == "2");
    CHECK(d.blocks[0].trials[0].cloud == std::filesystem::path("/d/a.pcd"));
    CHECK(d.practice.size() == 1);
    CHECK(d.break_s == 45.0);
    CHECK(d.participants == std::vector<std::string>{"P01", "P02"});
    CHECK(d.settings.hit_radius_m == 2.0);
    CHECK(d.settings.xres == 16);

    // P02 has the square's second row: plain first, then edl.
    const study::Session s = study::expandSession(d, "P02", "d.json");
    CHECK(s.condition_order == std::vector<int>{1, 0});
    REQUIRE(s.plan.trials.size() == 8);  // 2 conditions x (1 practice + 3 block trials)
    CHECK(s.trials[0].practice);
    CHECK(s.trials[0].block == -1);
    CHECK(s.trials[0].condition == 1);
    CHECK(s.plan.trials[0].source == "p.pcd");
    CHECK(s.trials[1].block == 0);
    CHECK(s.trials[3].block == 1);
    CHECK(s.plan.trials[1].candidates.empty());  // plain: no candidates
    CHECK(s.plan.trials[3].time_limit_s == 30.0);
    CHECK_FALSE(*s.plan.trials[1].eye_dome);
    CHECK(s.plan.trials[0].min_ready_s == 0.0);  // no break before the first condition
    CHECK(s.trials[4].condition == 0);
    CHECK(s.trials[4].practice);
    CHECK(s.plan.trials[4].min_ready_s == 45.0);  // the break before the second
    CHECK(s.plan.trials[5].candidates == std::filesystem::path("/d/a.json"));
    CHECK(s.plan.trials[5].time_limit_s == 60.0);  // edl's limit over the trial's
    CHECK(s.plan.trials[7].time_limit_s == 60.0);
    CHECK(*s.plan.trials[5].colour == viewer::ColourMode::HeightJet);
    CHECK(*s.plan.trials[1].start_mode == viewer::ViewMode::Free);  // plain starts free
    CHECK_FALSE(s.plan.trials[5].start_mode);                       // edl: the paper's automatic start
    CHECK_THROWS_WITH_AS(study::expandSession(d, "P99", "d.json"),
                         "study: --participant 'P99' is not in d.json's participants (P01, P02)", core::Error);
}

TEST_CASE("a design's refused keys: one line naming the key and what is allowed") {
    auto fails = [](const std::string& text, const std::string& message) {
        CAPTURE(text);
        CHECK_THROWS_WITH_AS(study::parseDesign(text, "design.json", "/"), message.c_str(), core::Error);
    };
    const std::string blocks = R"("blocks": [{"trials": [{"cloud": "a"}]}], "participants": ["P01"])";
    fails(R"({"conditions": [{"name": "a"}, {"name": "b", "colour": "hue"}], )" + blocks + "}",
          "study: design.json: conditions[1].colour 'hue' is not one of file, height, white, label, above-ground, "
          "class, intensity, return");
    fails(R"({"conditions": [], )" + blocks + "}",
          "study: design.json: 'conditions' must be a non-empty array, not an empty one");
    fails(R"({"conditions": [{"name": "a", "eye_dome": 1}], )" + blocks + "}",
          "study: design.json: conditions[0].eye_dome must be true or false, not a number");
    fails(R"({"conditions": [{"name": "a"}, {"name": "a"}], )" + blocks + "}",
          "study: design.json: conditions[1].name 'a' is used twice; allowed: a different name per condition");
    fails(R"({"conditions": [{"name": "a b"}], )" + blocks + "}",
          "study: design.json: conditions[0].name 'a b' is not a name of 1 to 40 letters, digits, '_', '-' or '.', "
          "not starting with '-'");
    // A name is written into CSV files as it is: none may read as a formula there.
    fails(R"({"conditions": [{"name": "-1+2"}], )" + blocks + "}",
          "study: design.json: conditions[0].name '-1+2' is not a name of 1 to 40 letters, digits, '_', '-' or '.', "
          "not starting with '-'");
    fails(R"({"conditions": [{"name": "a"}], "blocks": [{"trials": [{"cloud": "a"}]}], "participants": ["=1+2"]})",
          "study: design.json: participants[0] '=1+2' is not an id of 1 to 40 letters, digits, '_', '-' or '.', not "
          "starting with '-'");
    fails(R"({"conditions": [{"name": "a"}], "blocks": [{"trials": [{"cloud": "a"}]}], "participants": ["-P1"]})",
          "study: design.json: participants[0] '-P1' is not an id of 1 to 40 letters, digits, '_', '-' or '.', not "
          "starting with '-'");
    fails(R"({"conditions": [{"colour": "file"}], )" + blocks + "}",
          "study: design.json: conditions[0]: 'name' is required");
    fails(R"({"conditions": [{"name": "a", "time_limit_s": -2}], )" + blocks + "}",
          "study: design.json: conditions[0].time_limit_s -2 is not in [0, 86400]");
    fails(R"({"conditions": [{"name": "a", "sounds": []}], )" + blocks + "}",
          "study: design.json: conditions[0]: unknown key 'sounds'; allowed: name, colour, eye_dome, candidates, "
          "time_limit_s, start, detector, tools, cut, cut_radius_m, comment");
    fails(R"({"conditions": [{"name": "a", "tools": ["zoom", "laser"]}], )" + blocks + "}",
          "study: design.json: conditions[0].tools 'laser' is not one of zoom, cut, colour");
    fails(R"({"conditions": [{"name": "a", "tools": "zoom"}], )" + blocks + "}",
          "study: design.json: conditions[0].tools must be an array of tool names; allowed: zoom, cut, colour");
    fails(R"({"conditions": [{"name": "a", "detector": 3}], )" + blocks + "}",
          "study: design.json: conditions[0].detector must be a non-empty string; allowed: baseline, or a model file "
          "written by 'ladarvr train'");
    fails(R"({"conditions": [{"name": "a", "detector": "baseline", "candidates": false}], )" + blocks + "}",
          "study: design.json: conditions[0].detector goes with candidates shown; allowed: drop 'candidates': false");
    fails(
        R"({"conditions": [{"name": "a"}, {"name": "b", "detector": "m.ldm"}], "blocks": [{"trials": [{"scene": "s"}]}],
              "participants": ["P01"]})",
        "study: design.json: conditions[1].detector runs on cloud files; allowed: trials with 'cloud', not 'scene'");
    fails(R"({"conditions": [{"name": "a", "start": "orbit"}], )" + blocks + "}",
          "study: design.json: conditions[0].start 'orbit' is not one of automatic, free");
    fails(R"({"conditions": [{"name": "a", "start": 1}], )" + blocks + "}",
          "study: design.json: conditions[0].start must be a string, not a number; allowed: automatic, free");
    fails(R"({"conditions": [{"name": "a"}], "blocks": [{"trials": []}], "participants": ["P01"]})",
          "study: design.json: blocks[0].trials must be a non-empty array of trials");
    fails(R"({"conditions": [{"name": "a"}], "blocks": [{"trials": [{"cloud": "a", "time_limit_s": -1}]}],
              "participants": ["P01"]})",
          "study: design.json: blocks[0].trials[0].time_limit_s -1 is not in [0, 86400]");
    fails(R"({"conditions": [{"name": "a"}], "practice": [{}], )" + blocks + "}",
          "study: design.json: practice[0]: give exactly one of 'cloud' and 'scene'");
    fails(R"({"conditions": [{"name": "a"}], "order": "abba", )" + blocks + "}",
          "study: design.json: order 'abba' is not one of latin, permutation, random");
    fails(R"({"conditions": [{"name": "a"}], "order": "random", )" + blocks + "}",
          "study: design.json: order 'random' needs a 'seed' (a whole number >= 0), so orders are reproducible");
    fails(R"({"conditions": [{"name": "a"}], "seed": 3, )" + blocks + "}",
          "study: design.json: seed is only used with order 'random'");
    fails(R"({"conditions": [{"name": "a"}], "order": "random", "seed": -3, )" + blocks + "}",
          "study: design.json: seed must be a whole number >= 0, not -3");
    fails(R"({"conditions": [{"name": "a"}], "break_s": -1, )" + blocks + "}",
          "study: design.json: break_s -1 is not in [0, 86400]");
    fails(
        R"({"conditions": [{"name": "a"}], "blocks": [{"trials": [{"cloud": "a"}]}], "participants": ["P01", "P01"]})",
        "study: design.json: participants[1] 'P01' is listed twice; allowed: each id once");
    fails(R"({"conditions": [{"name": "a"}], "blocks": [{"trials": [{"cloud": "a"}]}]})",
          "study: design.json: 'participants' is required");
    fails(R"({"conditions": [{"name": "a"}], "trials": [], )" + blocks + "}",
          "study: design.json: unknown key 'trials'; allowed: conditions, blocks, practice, break_s, order, seed, "
          "participants, hit_radius_m, orbit, generate, questionnaires, comment");
    fails(R"({"conditions": )" + conditions(9) + R"(, "order": "permutation", )" + blocks + "}",
          "study: design.json: order 'permutation' with 9 conditions; allowed at most 8 (use 'latin')");
}

TEST_CASE("a design is told from a plan by its top-level 'conditions' key") {
    CHECK(study::isDesignText(R"({"conditions": [], "blocks": []})", "d.json"));
    CHECK_FALSE(study::isDesignText(R"({"trials": [{"cloud": "a"}]})", "d.json"));
    CHECK_FALSE(study::isDesignText("[1]", "d.json"));
}

TEST_CASE("a study file that is not strict JSON is reported as such, not taken for a plan") {
    const auto error = [](const std::string& text) {
        return test_support::errorOf([&] { study::isDesignText(text, "d.json"); });
    };
    CHECK(error("{not json").starts_with("study: d.json: JSON syntax error: "));
    CHECK(error(R"({"conditions": [], "conditions": []})") ==
          "study: d.json: duplicate key 'conditions'; allowed: each key once per object");
    CHECK(error(R"({"conditions": [{"name": "a", "time_limit_s": NaN}]})")
              .starts_with("study: d.json: JSON syntax error"));
    CHECK(error(R"({"conditions": []} trailing)").starts_with("study: d.json: JSON syntax error"));
    CHECK(error(std::string(1000, '[') + std::string(1000, ']')).find("nested deeper than") != std::string::npos);
}

TEST_CASE("Williams squares: positions and (even n) adjacent ordered pairs are balanced") {
    for (int n = 1; n <= 9; ++n) {
        CAPTURE(n);
        const auto rows = study::williamsSquare(n);
        const std::size_t want_rows = n % 2 == 0 ? std::size_t(n) : 2 * std::size_t(n);
        CHECK(rows.size() == (n == 1 ? 2 : want_rows));
        std::map<std::pair<int, int>, int> at;  // (position, condition) -> count
        std::map<std::pair<int, int>, int> pairs;
        for (const auto& row : rows) {
            std::vector<int> sorted = row;
            std::sort(sorted.begin(), sorted.end());
            for (int i = 0; i < n; ++i) CHECK(sorted[std::size_t(i)] == i);  // a permutation
            for (int i = 0; i < n; ++i) ++at[{i, row[std::size_t(i)]}];
            for (int i = 0; i + 1 < n; ++i) ++pairs[{row[std::size_t(i)], row[std::size_t(i) + 1]}];
        }
        const int per_position = static_cast<int>(rows.size()) / n;
        for (int pos = 0; pos < n; ++pos)
            for (int c = 0; c < n; ++c) CHECK(at[{pos, c}] == per_position);
        // Every ordered pair of different conditions is adjacent equally often: once for an
        // even n, twice over the 2n rows of an odd n.
        if (n > 1) {
            CHECK(pairs.size() == std::size_t(n * (n - 1)));
            for (const auto& [pair, count] : pairs) CHECK(count == (n % 2 == 0 ? 1 : 2));
        }
    }
}

TEST_CASE("the Latin order over a full square of participants puts each condition in each position equally") {
    for (int n : {3, 4}) {
        const study::Design d = design(n);
        std::map<std::pair<int, int>, int> at;
        for (std::size_t p = 0; p < d.participants.size(); ++p) {
            const auto order = study::conditionOrder(d, p);
            for (int i = 0; i < n; ++i) ++at[{i, order[std::size_t(i)]}];
        }
        for (const auto& [key, count] : at) CHECK(count == 2);  // 2n participants
        CHECK(at.size() == std::size_t(n * n));
        // The first participant has the first row, the n-th (odd n: 2n-th) wraps round.
        CHECK(study::conditionOrder(d, 0) == study::williamsSquare(n)[0]);
    }
    CHECK(study::conditionOrder(design(4), 0) == std::vector<int>{0, 1, 3, 2});
    CHECK(study::conditionOrder(design(4), 1) == std::vector<int>{1, 2, 0, 3});
    CHECK(study::conditionOrder(design(4), 4) == std::vector<int>{0, 1, 3, 2});
    CHECK(study::conditionOrder(design(3), 3) == std::vector<int>{2, 1, 0});  // the reversed first row
}

TEST_CASE("permutation cycles every order, and random is reproducible from its seed") {
    const study::Design p = design(3, "permutation");
    std::set<std::vector<int>> seen;
    for (std::size_t i = 0; i < 6; ++i) seen.insert(study::conditionOrder(p, i));
    CHECK(seen.size() == 6);
    CHECK(study::conditionOrder(p, 0) == std::vector<int>{0, 1, 2});
    CHECK(study::conditionOrder(p, 1) == std::vector<int>{0, 2, 1});
    CHECK(study::conditionOrder(p, 5) == std::vector<int>{2, 1, 0});
    CHECK(study::conditionOrder(p, 6) == std::vector<int>{0, 1, 2});

    const study::Design r = design(5, "random", R"(, "seed": 11)");
    const study::Design r2 = design(5, "random", R"(, "seed": 11)");
    const study::Design other = design(5, "random", R"(, "seed": 12)");
    bool differs_by_participant = false, differs_by_seed = false;
    for (std::size_t i = 0; i < r.participants.size(); ++i) {
        const auto order = study::conditionOrder(r, i);
        CHECK(order == study::conditionOrder(r2, i));
        std::vector<int> sorted = order;
        std::sort(sorted.begin(), sorted.end());
        CHECK(sorted == std::vector<int>{0, 1, 2, 3, 4});
        differs_by_participant = differs_by_participant || order != study::conditionOrder(r, 0);
        differs_by_seed = differs_by_seed || order != study::conditionOrder(other, i);
    }
    CHECK(differs_by_participant);
    CHECK(differs_by_seed);
}

TEST_CASE("readDesign checks the files the design names and gives the file's SHA-256") {
    test_support::TempDir dir("study_design");
    dir.write("a.pcd", "x");
    const auto bad = dir.write("bad.json", R"({"conditions": [{"name": "a"}],
        "blocks": [{"trials": [{"cloud": "a.pcd"}, {"cloud": "missing.pcd"}]}], "participants": ["P01"]})");
    CHECK_THROWS_WITH_AS(study::readDesign(bad), doctest::Contains("blocks[0].trials[1].cloud"), core::Error);
    const std::string text =
        R"({"conditions": [{"name": "a"}], "blocks": [{"trials": [{"cloud": "a.pcd"}]}], "participants": ["P01"]})";
    const auto ok = dir.write("ok.json", text);
    std::string sha;
    CHECK(study::readDesign(ok, &sha).blocks[0].trials[0].cloud == dir.path / "a.pcd");
    CHECK(sha.size() == 64);
    const auto changed = dir.write("changed.json", text + " ");
    std::string sha2;
    study::readDesign(changed, &sha2);
    CHECK(sha2 != sha);
}

TEST_CASE("a design's questionnaires: the SSQ, the TLX, Likert and text items, none by default") {
    const std::string head = R"({"conditions": [{"name": "a"}], "blocks": [{"trials": [{"cloud": "a.pcd"}]}],
        "participants": ["P01"])";
    const study::Design none = study::parseDesign(head + "}", "d.json", "/d");
    CHECK_FALSE(none.questionnaires.any());
    const study::Design d = study::parseDesign(head + R"(, "questionnaires": {"ssq": true, "tlx": true,
        "likert": [{"id": "confident", "statement": "I was confident in my answers.", "points": 5,
                    "when": "after_condition"},
                   {"id": "enjoyed", "statement": "I enjoyed the task.", "when": "post"}],
        "text": [{"id": "remarks", "question": "Anything else?", "when": "pre"}]}})",
                                               "d.json", "/d");
    const study::Questionnaires& q = d.questionnaires;
    CHECK(q.any());
    CHECK(q.ssq);
    CHECK(q.tlx);
    REQUIRE(q.likert.size() == 2);
    CHECK(q.likert[0].id == "confident");
    CHECK(q.likert[0].statement == "I was confident in my answers.");
    CHECK(q.likert[0].points == 5);
    CHECK(q.likert[0].when == study::QuestionWhen::AfterCondition);
    CHECK(q.likert[1].points == 7);  // the default
    CHECK(q.likert[1].when == study::QuestionWhen::Post);
    REQUIRE(q.text.size() == 1);
    CHECK(q.text[0].id == "remarks");
    CHECK(q.text[0].question == "Anything else?");
    CHECK(q.text[0].when == study::QuestionWhen::Pre);
    CHECK(std::string(study::questionWhenName(study::QuestionWhen::AfterCondition)) == "after_condition");
    const study::Design ssq_only = study::parseDesign(head + R"(, "questionnaires": {"ssq": true}})", "d.json", "/d");
    CHECK(ssq_only.questionnaires.ssq);
    CHECK_FALSE(ssq_only.questionnaires.tlx);
}

TEST_CASE("a design's refused questionnaire keys: one line naming the key and what is allowed") {
    const std::string head = R"({"conditions": [{"name": "a"}], "blocks": [{"trials": [{"cloud": "a"}]}],
        "participants": ["P01"], "questionnaires": )";
    auto fails = [&](const std::string& q, const std::string& message) {
        CAPTURE(q);
        CHECK_THROWS_WITH_AS(study::parseDesign(head + q + "}", "design.json", "/"), message.c_str(), core::Error);
    };
    fails("[]", "study: design.json: questionnaires must be an object, not an array");
    fails(R"({"ssq": "yes"})", "study: design.json: questionnaires.ssq must be true or false, not a string");
    fails(R"({"tlx": 1})", "study: design.json: questionnaires.tlx must be true or false, not a number");
    fails(R"({"sus": true})",
          "study: design.json: questionnaires: unknown key 'sus'; allowed: ssq, tlx, likert, text, comment");
    fails(R"({"likert": {}})", "study: design.json: questionnaires: 'likert' must be an array, not an object");
    fails(R"({"likert": [{"statement": "s", "when": "post"}]})",
          "study: design.json: questionnaires.likert[0]: 'id' is required");
    fails(R"({"likert": [{"id": "a b", "statement": "s", "when": "post"}]})",
          "study: design.json: questionnaires.likert[0].id 'a b' is not a name of 1 to 40 letters, digits, '_', '-' "
          "or '.', not starting with '-'");
    fails(R"({"likert": [{"id": "a", "when": "post"}]})",
          "study: design.json: questionnaires.likert[0]: 'statement' is required");
    fails(R"({"likert": [{"id": "a", "statement": "", "when": "post"}]})",
          "study: design.json: questionnaires.likert[0].statement must be a string of 1 to 300 characters without "
          "control characters, not one of 0 characters");
    fails(R"({"likert": [{"id": "a", "statement": "two\nlines", "when": "post"}]})",
          "study: design.json: questionnaires.likert[0].statement must be a string of 1 to 300 characters without "
          "control characters, not one of 9 characters with a control character");
    fails(R"({"likert": [{"id": "a", "statement": "s", "points": 1, "when": "post"}]})",
          "study: design.json: questionnaires.likert[0].points 1 is not in [2, 11]");
    fails(R"({"likert": [{"id": "a", "statement": "s", "points": 12, "when": "post"}]})",
          "study: design.json: questionnaires.likert[0].points 12 is not in [2, 11]");
    fails(R"({"likert": [{"id": "a", "statement": "s", "points": 4.5, "when": "post"}]})",
          "study: design.json: questionnaires.likert[0].points 4.5 is not a whole number");
    fails(R"({"likert": [{"id": "a", "statement": "s"}]})",
          "study: design.json: questionnaires.likert[0]: 'when' is required (pre, post or after_condition)");
    fails(R"({"likert": [{"id": "a", "statement": "s", "when": "during"}]})",
          "study: design.json: questionnaires.likert[0].when 'during' is not one of pre, post, after_condition");
    fails(R"({"likert": [{"id": "a", "statement": "s", "when": "post", "scale": 5}]})",
          "study: design.json: questionnaires.likert[0]: unknown key 'scale'; allowed: id, statement, points, when, "
          "comment");
    fails(R"({"likert": [{"id": "a", "statement": "s", "when": "post"}], "text": [{"id": "a", "question": "q",
              "when": "post"}]})",
          "study: design.json: questionnaires.text[0].id 'a' is used twice; allowed: a different id per item");
    fails(R"({"text": [{"id": "t", "statement": "q", "when": "post"}]})",
          "study: design.json: questionnaires.text[0]: unknown key 'statement'; allowed: id, question, when, comment");
}

TEST_CASE("a condition's detector: the baseline, or a model file relative to the design") {
    const study::Design d = study::parseDesign(R"({
        "conditions": [{"name": "atr", "detector": "models/m.ldm"}, {"name": "base", "detector": "baseline"},
                       {"name": "none"}],
        "blocks": [{"trials": [{"cloud": "a.pcd", "candidates": "a.json"}]}], "participants": ["P01"]})",
                                               "d.json", "/d");
    CHECK(d.conditions[0].detector == "/d/models/m.ldm");
    CHECK(d.conditions[1].detector == "baseline");
    CHECK(d.conditions[2].detector.empty());
    const study::Session s = study::expandSession(d, "P01", "d.json");
    REQUIRE(s.plan.trials.size() == 3);
    for (std::size_t i = 0; i < 3; ++i) {
        const std::string want = d.conditions[std::size_t(s.trials[i].condition)].detector;
        CHECK(s.plan.trials[i].detector == want);
        CHECK(s.plan.trials[i].candidates == std::filesystem::path("/d/a.json"));  // kept; the detector's replace them
    }
}

TEST_CASE("a condition's tools: the ones named are offered, none with an empty list") {
    const study::Design d = study::parseDesign(R"({
        "conditions": [{"name": "all"}, {"name": "some", "tools": ["cut", "zoom"]}, {"name": "none", "tools": []}],
        "blocks": [{"trials": [{"cloud": "a.pcd"}]}], "participants": ["P01"]})",
                                               "d.json", "/d");
    CHECK_FALSE(d.conditions[0].tools);
    CHECK(*d.conditions[1].tools == (viewer::kToolCut | viewer::kToolZoom));
    CHECK(*d.conditions[2].tools == 0u);
    const study::Session s = study::expandSession(d, "P01", "d.json");
    for (std::size_t i = 0; i < s.plan.trials.size(); ++i)
        CHECK(s.plan.trials[i].tools == d.conditions[std::size_t(s.trials[i].condition)].tools);
}

TEST_CASE("a condition's cutting volume: on or off at each trial's start, and its radius") {
    const study::Design d = study::parseDesign(R"({
        "conditions": [{"name": "cut", "cut": true, "cut_radius_m": 8, "tools": []}, {"name": "plain", "cut": false},
                       {"name": "as_run"}],
        "blocks": [{"trials": [{"cloud": "a.pcd"}]}], "participants": ["P01"]})",
                                               "d.json", "/d");
    CHECK(d.conditions[0].cut == std::optional<bool>(true));
    CHECK(d.conditions[0].cut_radius_m == std::optional<double>(8.0));
    CHECK(d.conditions[1].cut == std::optional<bool>(false));
    CHECK_FALSE(d.conditions[2].cut);
    CHECK_FALSE(d.conditions[2].cut_radius_m);
    const study::Session s = study::expandSession(d, "P01", "d.json");
    for (std::size_t i = 0; i < s.plan.trials.size(); ++i) {
        const study::Condition& c = d.conditions[std::size_t(s.trials[i].condition)];
        CHECK(s.plan.trials[i].cut == c.cut);
        CHECK(s.plan.trials[i].cut_radius_m == c.cut_radius_m);
    }
    const std::string blocks = R"("blocks": [{"trials": [{"cloud": "a"}]}], "participants": ["P1"])";
    CHECK(test_support::errorOf([&] {
              study::parseDesign(R"({"conditions": [{"name": "a", "cut": 1}], )" + blocks + "}", "design.json", "/d");
          }).find("conditions[0].cut") != std::string::npos);
    CHECK(test_support::errorOf([&] {
              study::parseDesign(R"({"conditions": [{"name": "a", "cut_radius_m": 0}], )" + blocks + "}", "design.json",
                                 "/d");
          }) == "study: design.json: conditions[0].cut_radius_m 0 is not in [0.1, 10000]");
}

TEST_CASE("a block picked from a corpus by difficulty: its items become the block's cloud trials") {
    test_support::TempDir dir("design_corpus_block");
    std::string manifest;
    for (int i = 0; i < 4; ++i) {
        const std::string id = "000" + std::to_string(i);
        std::filesystem::create_directories(dir.path / "corpus" / "items" / id);
        std::ofstream(dir.path / "corpus" / "items" / id / "cloud.pcd") << "x";
        manifest += R"({"id": ")" + id + R"(", "index": )" + std::to_string(i) + R"(, "metric": )" +
                    std::to_string(0.1 * (i + 1)) + R"(, "files": {"cloud.pcd": {"bytes": 1}}})" + "\n";
    }
    dir.write("corpus/manifest.jsonl", manifest);
    dir.write("design.json", R"({"conditions": [{"name": "a"}, {"name": "b"}],
        "blocks": [{"name": "hard", "corpus": "corpus", "select": "metric<0.35", "count": 2, "seed": 3,
                    "time_limit_s": 45}],
        "participants": ["P01"]})");
    const study::Design d = study::readDesign(dir.path / "design.json");
    REQUIRE(d.blocks.size() == 1);
    REQUIRE(d.blocks[0].trials.size() == 2);
    std::set<std::string> names;
    for (const study::PlanTrial& t : d.blocks[0].trials) {
        CHECK(t.cloud.filename() == "cloud.pcd");
        CHECK(std::filesystem::is_regular_file(t.cloud));
        CHECK(t.time_limit_s == 45.0);
        names.insert(t.name);
    }
    // metric < 0.35: items 0000, 0001, 0002; two of them, the same two on every read.
    CHECK(names.count("item 0003") == 0);
    const study::Design again = study::readDesign(dir.path / "design.json");
    CHECK(again.blocks[0].trials[0].cloud == d.blocks[0].trials[0].cloud);
    CHECK(again.blocks[0].trials[1].cloud == d.blocks[0].trials[1].cloud);
    CHECK(study::expandSession(d, "P01", "design.json").plan.trials.size() == 4);

    dir.write("design5.json", R"({"conditions": [{"name": "a"}],
        "blocks": [{"corpus": "corpus", "select": "metric<0.35", "count": 5}], "participants": ["P01"]})");
    CHECK_THROWS_WITH_AS(
        study::readDesign(dir.path / "design5.json"),
        doctest::Contains("blocks[0]: corpus: count 5: 3 of 4 items match 'metric<0.35'; allowed 1..3"), core::Error);
}

TEST_CASE("a corpus block's refused forms: one line naming the key") {
    auto fails = [](const std::string& block, const std::string& message) {
        const std::string text =
            R"({"conditions": [{"name": "a"}], "blocks": [)" + block + R"(], "participants": ["P01"]})";
        CAPTURE(text);
        CHECK_THROWS_WITH_AS(study::parseDesign(text, "design.json", "/"), message.c_str(), core::Error);
    };
    fails(R"({"corpus": "c", "count": 2})",
          "study: design.json: blocks[0]: 'select' is required with 'corpus' (a manifest condition, e.g. "
          "\"metric<0.3\")");
    fails(R"({"corpus": "c", "select": "metric<1"})",
          "study: design.json: blocks[0]: 'count' is required with 'corpus' (1 to 1000 items)");
    fails(R"({"corpus": "c", "select": "metric<1", "count": 2, "trials": [{"cloud": "a"}]})",
          "study: design.json: blocks[0]: give either 'trials' or 'corpus' with 'select' and 'count', not both");
    fails(R"({"trials": [{"cloud": "a"}], "count": 2})", "study: design.json: blocks[0]: 'count' goes with 'corpus'");
}

TEST_CASE("a design whose blocks are all from a corpus expands, before they are picked, to no trials and no break") {
    // readDesign fills a corpus block with its items; parseDesign alone leaves it empty, and
    // a condition without a trial has no first trial to carry the break.
    const study::Design d = study::parseDesign(
        R"({"conditions": [{"name": "a"}, {"name": "b"}], "break_s": 30,
            "blocks": [{"corpus": "c", "select": "metric<1", "count": 2}], "participants": ["P1"]})",
        "d.json", "/d");
    const study::Session s = study::expandSession(d, "P1", "d.json");
    CHECK(s.condition_order.size() == 2);
    CHECK(s.plan.trials.empty());
    CHECK(s.trials.empty());
}

TEST_CASE("a design's paths with a NUL character are refused in one line (the strict JSON reader's rule)") {
    CHECK_THROWS_WITH_AS(
        study::parseDesign(R"({"conditions": [{"name": "a"}],
            "blocks": [{"corpus": "c\u0000d", "select": "metric<1", "count": 2}], "participants": ["P1"]})",
                           "d.json", "/"),
        "study: d.json: blocks[0].corpus: the string 'c\\x00d' holds a NUL character (\\u0000); allowed: text "
        "without NUL",
        core::Error);
    CHECK_THROWS_WITH_AS(
        study::parseDesign(R"({"conditions": [{"name": "a", "detector": "m\u0000.ldm"}],
            "blocks": [{"trials": [{"cloud": "x"}]}], "participants": ["P1"]})",
                           "d.json", "/"),
        "study: d.json: conditions[0].detector: the string 'm\\x00.ldm' holds a NUL character (\\u0000); "
        "allowed: text without NUL",
        core::Error);
}

TEST_CASE("the study files' fuzz seeds: each a plan or design read, or one line, as fuzz_study_file expects") {
    // fuzz/seeds/study (fuzz/make_seeds.py): the examples of docs/study.md and refused forms.
    const std::filesystem::path seeds = std::filesystem::path(test_support::fuzzSeedsDir()) / "study";
    int read = 0, refused = 0;
    for (const auto& entry : std::filesystem::directory_iterator(seeds)) {
        const std::string text = test_support::slurp(entry.path());
        CAPTURE(entry.path().string());
        try {
            std::size_t trials = 0;
            if (study::isDesignText(text, "seed.json")) {
                const study::Design d = study::parseDesign(text, "seed.json", "/s");
                for (std::size_t p = 0; p < d.participants.size(); ++p) {
                    const study::Session s = study::expandSession(d, d.participants[p], "seed.json");
                    CHECK(s.condition_order.size() == d.conditions.size());
                    trials += s.plan.trials.size();
                }
                trials += d.blocks.size();  // a corpus-only design has no trial before its items are picked
            } else {
                trials = study::parsePlan(text, "seed.json", "/s").trials.size();
            }
            CHECK(trials > 0);
            ++read;
        } catch (const core::Error& e) {
            const std::string m = e.what();
            CHECK(m.rfind("study: seed.json: ", 0) == 0);
            CHECK(m.find('\n') == std::string::npos);
            CHECK(entry.path().filename().string().find("errors") != std::string::npos);
            ++refused;
        }
    }
    CHECK(read >= 5);
    CHECK(refused >= 2);
}
