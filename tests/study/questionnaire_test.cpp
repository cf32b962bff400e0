// tests/study/questionnaire_test.cpp: when a session asks its questionnaires (the gaps
// between trials, the order within a gap, the condition each answer belongs to) and the
// rows of questionnaires.csv.
#include <study/questionnaire.hpp>

#include <study/instruments.hpp>

#include <doctest/doctest.h>

#include <string>

namespace {
study::Design twoConditions(const std::string& questionnaires) {
    return study::parseDesign(R"({"conditions": [{"name": "a"}, {"name": "b"}],
        "practice": [{"cloud": "p.pcd"}], "blocks": [{"trials": [{"cloud": "x.pcd"}]}],
        "participants": ["P01", "P02"], "questionnaires": )" +
                                  questionnaires + "}",
                              "d.json", "/d");
}
}  // namespace

TEST_CASE("the schedule: SSQ before the first trial and after the last, TLX after each condition") {
    const study::Design d = twoConditions(R"({"ssq": true, "tlx": true,
        "likert": [{"id": "sure", "statement": "I was sure.", "points": 5, "when": "after_condition"},
                   {"id": "liked", "statement": "I liked it.", "when": "post"},
                   {"id": "rested", "statement": "I feel rested.", "when": "pre"}],
        "text": [{"id": "remarks", "question": "Anything else?", "when": "post"}]})");
    // P02 gets the Williams square's second row for two conditions: b, then a.
    const study::Session s = study::expandSession(d, "P02", "d.json");
    REQUIRE(s.trials.size() == 4);
    const auto q = study::questionSchedule(d, s);
    REQUIRE(q.size() == 16 + 1 + (6 + 1) + (6 + 1) + 16 + 1 + 1);
    std::size_t k = 0;
    for (int i = 0; i < 16; ++i, ++k) {
        CHECK(q[k].gap == 0);
        CHECK(q[k].instrument == study::Instrument::Ssq);
        CHECK(q[k].when == study::QuestionWhen::Pre);
        CHECK(q[k].condition.empty());
        CHECK(q[k].item == study::ssqItems()[std::size_t(i)].item.id);
        CHECK(q[k].min == 0);
        CHECK(q[k].max == 3);
        CHECK(q[k].number == i + 1);
        CHECK(q[k].count == 16);
    }
    CHECK(q[k].item == "rested");
    CHECK(q[k].gap == 0);
    CHECK(q[k].max == 7);
    ++k;
    for (const char* condition : {"b", "a"}) {
        const std::size_t gap = std::string(condition) == "b" ? 2 : 4;
        for (int i = 0; i < 6; ++i, ++k) {
            CHECK(q[k].gap == gap);
            CHECK(q[k].instrument == study::Instrument::Tlx);
            CHECK(q[k].when == study::QuestionWhen::AfterCondition);
            CHECK(q[k].condition == condition);
            CHECK(q[k].item == study::tlxItems()[std::size_t(i)].id);
            CHECK(q[k].max == 100);
            CHECK(q[k].step == 5);
        }
        CHECK(q[k].item == "sure");
        CHECK(q[k].instrument == study::Instrument::Likert);
        CHECK(q[k].condition == condition);
        CHECK(q[k].min == 1);
        CHECK(q[k].max == 5);
        ++k;
    }
    for (int i = 0; i < 16; ++i, ++k) {
        CHECK(q[k].gap == 4);
        CHECK(q[k].when == study::QuestionWhen::Post);
        CHECK(q[k].condition == "a");  // the condition just run
        CHECK(q[k].instrument == study::Instrument::Ssq);
    }
    CHECK(q[k].item == "liked");
    CHECK(q[k].when == study::QuestionWhen::Post);
    ++k;
    CHECK(q[k].item == "remarks");
    CHECK(q[k].instrument == study::Instrument::Text);
    CHECK(q[k].gap == 4);
}

TEST_CASE("no questionnaires: an empty schedule") {
    const study::Design d = study::parseDesign(R"({"conditions": [{"name": "a"}],
        "blocks": [{"trials": [{"cloud": "x.pcd"}]}], "participants": ["P01"]})",
                                               "d.json", "/d");
    CHECK(study::questionSchedule(d, study::expandSession(d, "P01", "d.json")).empty());
    const study::Design off = twoConditions(R"({"ssq": false, "tlx": false})");
    CHECK(study::questionSchedule(off, study::expandSession(off, "P01", "d.json")).empty());
}

TEST_CASE("questionnaires.csv's rows: the layout of study/instruments.hpp, text quoted") {
    CHECK(std::string(study::questionnairesHeader()) ==
          "participant,condition,instrument,occasion,item,response,time_s");
    const study::Design d = twoConditions(R"({"tlx": true,
        "text": [{"id": "remarks", "question": "Anything else?", "when": "after_condition"}]})");
    const auto q = study::questionSchedule(d, study::expandSession(d, "P01", "d.json"));
    REQUIRE(q.size() == 14);
    CHECK(study::questionnaireRow("P01", q[0], "35", 12.25) == "P01,a,tlx,after_condition,mental,35,12.250000");
    CHECK(study::questionnaireRow("P01", q[6], "fine, \"thanks\"", 1.0) ==
          "P01,a,text,after_condition,remarks,\"fine, \"\"thanks\"\"\",1.000000");
    CHECK(study::questionnaireRow("P01", q[6], "", 1.0) == "P01,a,text,after_condition,remarks,,1.000000");
    // A free-text answer is text in a spreadsheet, never a formula, and stays on its line.
    CHECK(study::questionnaireRow("P01", q[6], "=HYPERLINK(\"http://x\")", 1.0) ==
          "P01,a,text,after_condition,remarks,\"'=HYPERLINK(\"\"http://x\"\")\",1.000000");
    CHECK(study::questionnaireRow("P01", q[6], "-1+1\n\x1b[2J", 1.0) ==
          "P01,a,text,after_condition,remarks,'-1+1\\x0a\\x1b[2J,1.000000");
}
