// tests/viewer/script_test.cpp: viewer::parseScript on text in memory (the function the
// fuzz target fuzz_view_script drives): accepted forms, refused lines, escaped messages.
#include <viewer/script.hpp>

#include <core/error.hpp>

#include <doctest/doctest.h>

#include <string>

using viewer::parseScript;
using viewer::ScriptEvent;

namespace {
const std::string kName = "view: --script s.txt";
}

TEST_CASE("script text: tabs, CRLF line ends, comments and blank lines") {
    const auto events = parseScript("0\tspace\r\n\r\n  7 escape # stop\r\n#only a comment\n", kName);
    REQUIRE(events.size() == 2);
    CHECK(events[0].frame == 0);
    CHECK(events[0].key == ScriptEvent::Key::Space);
    CHECK(events[1].frame == 7);
    CHECK(events[1].key == ScriptEvent::Key::Escape);
    CHECK(parseScript("", kName).empty());
    CHECK(parseScript("# nothing\n\n", kName).empty());
    // The last line needs no newline.
    REQUIRE(parseScript("12 space", kName).size() == 1);
}

TEST_CASE("script text: refused frames name the line and what is allowed") {
    CHECK_THROWS_WITH_AS(
        parseScript("1 space\n99999999999999999999 space\n", kName),
        "view: --script s.txt line 2: frame '99999999999999999999' is not a whole number from 0 to 1000000000; "
        "allowed '<frame> space|escape|designate|confirm|reject|no_target|next|cut|colour', '<frame> aim X Y Z', "
        "'<frame> grab_scale S', '<frame> answer TEXT', '<frame> point_answer N', <frame> N, desktop+N, loaded+N, "
        "pickable+N or +N",
        core::Error);
    CHECK_THROWS_WITH_AS(parseScript("0x10 space\n", kName), doctest::Contains("line 1: frame '0x10'"), core::Error);
    CHECK_THROWS_WITH_AS(parseScript("1.5 space\n", kName), doctest::Contains("frame '1.5'"), core::Error);
    CHECK_THROWS_WITH_AS(parseScript("-1 space\n", kName), doctest::Contains("frame '-1'"), core::Error);
    CHECK_THROWS_WITH_AS(parseScript("\n\n5\n", kName), doctest::Contains("line 3: missing action"), core::Error);
}

TEST_CASE("script text: bytes from a binary file, or a token that is no script word, are not shown") {
    const std::string key = std::string("sp\x1b[2J") + '\0' + "ace";
    CHECK_THROWS_WITH_AS(parseScript("3 " + key + "\n", kName),
                         doctest::Contains("line 1: action (10 bytes, not shown) is not one of space, escape"),
                         core::Error);
    // A password file named as a script: nothing of its line reaches the message.
    try {
        parseScript("root:$y$j9T$abcdefgh:20786:0:99999:7:::\n", kName);
        FAIL("a password file's line was accepted");
    } catch (const core::Error& e) {
        const std::string what = e.what();
        CHECK(what.find("line 1: frame (39 bytes, not shown) is not a whole number") != std::string::npos);
        CHECK(what.find("root") == std::string::npos);
    }
    try {
        parseScript("4 space " + std::string(5000, '\x7f') + "\n", kName);
        FAIL("a long binary token was accepted");
    } catch (const core::Error& e) {
        const std::string what = e.what();
        CHECK(what.size() < 400);
        CHECK(what.find('\x7f') == std::string::npos);
        CHECK(what.find("unexpected (5000 bytes, not shown)") != std::string::npos);
    }
}

TEST_CASE("script text: the operator's actions, with their arguments") {
    const auto events = parseScript(
        "3 next\n5 aim 10.5 -20 1e2\n6 designate\n7 confirm\n8 reject\n"
        "9 no_target\n10 grab_scale 2.5\n",
        kName);
    REQUIRE(events.size() == 7);
    CHECK(events[0].key == ScriptEvent::Key::Next);
    CHECK(events[1].key == ScriptEvent::Key::Aim);
    CHECK(events[1].point[0] == 10.5);
    CHECK(events[1].point[1] == -20.0);
    CHECK(events[1].point[2] == 100.0);
    CHECK(events[2].key == ScriptEvent::Key::Designate);
    CHECK(events[3].key == ScriptEvent::Key::Confirm);
    CHECK(events[4].key == ScriptEvent::Key::Reject);
    CHECK(events[5].key == ScriptEvent::Key::NoTarget);
    CHECK(events[6].key == ScriptEvent::Key::GrabScale);
    CHECK(events[6].value == 2.5);
    // Written back, the same events.
    const auto again = parseScript(viewer::formatScript(events), kName);
    REQUIRE(again.size() == events.size());
    for (std::size_t i = 0; i < events.size(); ++i) {
        CHECK(again[i].key == events[i].key);
        CHECK(again[i].frame == events[i].frame);
        CHECK(again[i].value == events[i].value);
        CHECK(again[i].point[0] == events[i].point[0]);
    }
}

TEST_CASE("script text: arguments are checked") {
    CHECK_THROWS_WITH_AS(parseScript("1 aim 1 2\n", kName), doctest::Contains("line 1: aim needs X Y Z"), core::Error);
    CHECK_THROWS_WITH_AS(parseScript("1 aim 1 2 inf\n", kName), doctest::Contains("aim coordinate 'inf'"), core::Error);
    CHECK_THROWS_WITH_AS(parseScript("1 aim 1 2 1e999\n", kName), doctest::Contains("'1e999' is not a finite"),
                         core::Error);
    CHECK_THROWS_WITH_AS(parseScript("1 aim 1 2 3 4\n", kName), doctest::Contains("unexpected '4'"), core::Error);
    CHECK_THROWS_WITH_AS(parseScript("1 grab_scale 0\n", kName),
                         doctest::Contains("grab_scale '0' is not a finite number > 0"), core::Error);
    CHECK_THROWS_WITH_AS(parseScript("1 grab_scale\n", kName), doctest::Contains("grab_scale needs a scale"),
                         core::Error);
    CHECK_THROWS_WITH_AS(parseScript("1 designate now\n", kName), doctest::Contains("unexpected 'now'"), core::Error);
}

TEST_CASE("script text: +N counts from the previous action") {
    const auto events = parseScript("1 next\n+10 designate\n+0 confirm\n", kName);
    REQUIRE(events.size() == 3);
    CHECK_FALSE(events[0].relative);
    CHECK(events[1].relative);
    CHECK(events[1].frame == 10);
    CHECK(events[2].relative);
    CHECK(events[2].frame == 0);
    const auto again = parseScript(viewer::formatScript(events), kName);
    CHECK(again[1].relative);
    CHECK(again[1].frame == 10);
    CHECK_THROWS_WITH_AS(parseScript("+ next\n", kName), doctest::Contains("frame '+'"), core::Error);
    CHECK_THROWS_WITH_AS(parseScript("+-3 next\n", kName), doctest::Contains("frame '+-3'"), core::Error);
    CHECK_THROWS_WITH_AS(parseScript("++3 next\n", kName), doctest::Contains("frame '++3'"), core::Error);
}

TEST_CASE("script text: loaded+N counts from the whole cloud being on the GPU") {
    const auto events = parseScript("loaded+5 escape\ndesktop+2 space\n", kName);
    REQUIRE(events.size() == 2);
    CHECK(events[0].after_loaded);
    CHECK_FALSE(events[0].after_desktop);
    CHECK_FALSE(events[0].relative);
    CHECK(events[0].frame == 5);
    CHECK(events[1].after_desktop);
    CHECK_FALSE(events[1].after_loaded);
    const auto again = parseScript(viewer::formatScript(events), kName);
    REQUIRE(again.size() == 2);
    CHECK(again[0].after_loaded);
    CHECK(again[0].frame == 5);
    CHECK_THROWS_WITH_AS(parseScript("loaded+ escape\n", kName), doctest::Contains("frame 'loaded+'"), core::Error);
    CHECK_THROWS_WITH_AS(parseScript("loaded5 escape\n", kName), doctest::Contains("frame 'loaded5'"), core::Error);
}

TEST_CASE("script text: pickable+N counts from the pointer's first pick index") {
    const auto events = parseScript("pickable+3 designate\nloaded+1 space\n", kName);
    REQUIRE(events.size() == 2);
    CHECK(events[0].after_pickable);
    CHECK_FALSE(events[0].after_loaded);
    CHECK_FALSE(events[0].relative);
    CHECK(events[0].frame == 3);
    CHECK_FALSE(events[1].after_pickable);
    CHECK(viewer::formatScript(events) == "pickable+3 designate\nloaded+1 space\n");
    CHECK_THROWS_WITH_AS(parseScript("pickable+ designate\n", kName), doctest::Contains("frame 'pickable+'"),
                         core::Error);
}

TEST_CASE("script text: answer takes the rest of the line, trimmed, and writes back") {
    const auto events = parseScript("+1 answer 3\n+1 answer  it was fine, mostly \r\n", kName);
    REQUIRE(events.size() == 2);
    CHECK(events[0].key == ScriptEvent::Key::Answer);
    CHECK(events[0].relative);
    CHECK(events[0].text == "3");
    CHECK(events[1].text == "it was fine, mostly");
    CHECK(viewer::formatScript(events) == "+1 answer 3\n+1 answer it was fine, mostly\n");
    CHECK(parseScript(viewer::formatScript(events), kName)[1].text == events[1].text);
    CHECK_THROWS_WITH_AS(parseScript("1 answer   \n", kName),
                         doctest::Contains("line 1: answer needs a rating or a text"), core::Error);
    const auto pointed = parseScript("+1 point_answer 35\n", kName);
    REQUIRE(pointed.size() == 1);
    CHECK(pointed[0].key == ScriptEvent::Key::PointAnswer);
    CHECK(pointed[0].value == 35.0);
    CHECK(viewer::formatScript(pointed) == "+1 point_answer 35\n");
    CHECK_THROWS_WITH_AS(parseScript("1 point_answer 2.5\n", kName),
                         doctest::Contains("point_answer '2.5' is not a whole number"), core::Error);
    CHECK_THROWS_WITH_AS(parseScript("1 point_answer\n", kName), doctest::Contains("point_answer needs a rating N"),
                         core::Error);
    CHECK_THROWS_WITH_AS(parseScript("1 answer " + std::string(1001, 'x') + "\n", kName),
                         doctest::Contains("answer of 1001 bytes; at most 1000"), core::Error);
}

TEST_CASE("script text: frames are at most kMaxScriptFrame, alone and added up by +N lines") {
    CHECK(parseScript("1000000000 space\n", kName)[0].frame == viewer::kMaxScriptFrame);
    CHECK_THROWS_WITH_AS(parseScript("1000000001 space\n", kName),
                         doctest::Contains("line 1: frame '1000000001' is not a whole number from 0 to 1000000000"),
                         core::Error);
    // A relative frame so large that adding it to the frame it follows would overflow.
    CHECK_THROWS_WITH_AS(parseScript("3 space\n+9223372036854775806 escape\n", kName),
                         doctest::Contains("line 2: frame '+9223372036854775806' is not a whole number from 0 to "
                                           "1000000000"),
                         core::Error);
    CHECK_THROWS_WITH_AS(parseScript("loaded+9223372036854775806 escape\n", kName),
                         doctest::Contains("line 1: frame 'loaded+9223372036854775806'"), core::Error);
    // Each +N within the bound, their sum past it.
    CHECK_THROWS_WITH_AS(parseScript("600000000 space\n+300000000 space\n+100000001 escape\n", kName),
                         doctest::Contains("line 3: frame '+100000001' puts the action 1000000001 frames after the "
                                           "start (or the last desktop+, loaded+ or pickable+ line); at most "
                                           "1000000000"),
                         core::Error);
    // An absolute or anchored line starts the sum again.
    CHECK(parseScript("600000000 space\n+300000000 space\nloaded+600000000 space\n+400000000 escape\n", kName).size() ==
          4);
}

TEST_CASE("script text: cut and colour, the V and C keys' actions") {
    const auto events = parseScript("4 cut\n+1 colour\n", kName);
    REQUIRE(events.size() == 2);
    CHECK(events[0].key == viewer::ScriptEvent::Key::Cut);
    CHECK(events[1].key == viewer::ScriptEvent::Key::Colour);
    CHECK(viewer::formatScript(events) == "4 cut\n+1 colour\n");
    CHECK_THROWS_WITH_AS(parseScript("1 cutt\n", kName), doctest::Contains("point_answer, cut, colour"), core::Error);
}
