// tests/viewer/input/script_player_test.cpp: a --script's events played against the frame count
// (viewer/src/input/script_player.cpp): each action at its frame, +N after the one before,
// and a relative frame the parser would refuse never due at once.
#include "input/script_player.hpp"

#include <doctest/doctest.h>

#include <limits>

using namespace viewer;

namespace {

ScriptEvent event(long frame, ScriptEvent::Key key, bool relative = false) {
    ScriptEvent ev;
    ev.frame = frame;
    ev.key = key;
    ev.relative = relative;
    return ev;
}

}  // namespace

TEST_CASE("script player: actions at their frames, +N counted from the action before") {
    ScriptPlayer p({event(3, ScriptEvent::Key::Space), event(2, ScriptEvent::Key::Escape, true)});
    ScriptClock clock;
    for (clock.frame = 0; clock.frame < 3; ++clock.frame) CHECK_FALSE(p.take(clock).toggle_mode);
    const OperatorInput at3 = p.take(clock);
    CHECK(at3.toggle_mode);
    CHECK_FALSE(at3.quit);
    clock.frame = 4;
    CHECK_FALSE(p.take(clock).quit);
    clock.frame = 5;
    CHECK(p.take(clock).quit);
}

TEST_CASE("script player: a relative frame near the largest long is not due at once") {
    // `3 space` then `+9223372036854775806 escape` (as events: the parser refuses the
    // second line): the frame and its base must not add up past the largest long.
    ScriptPlayer p({event(3, ScriptEvent::Key::Space),
                    event(std::numeric_limits<long>::max() - 1, ScriptEvent::Key::Escape, true)});
    ScriptClock clock;
    clock.frame = 3;
    const OperatorInput in = p.take(clock);
    CHECK(in.toggle_mode);
    CHECK_FALSE(in.quit);
    clock.frame = 1000000;
    CHECK_FALSE(p.take(clock).quit);
}

TEST_CASE("script player: a next waits while a questionnaire is up, then dismisses the ready screen") {
    // `1 point_answer 4` then `+2 next`: the click takes frames to go through the panel,
    // during which the next must not be spent on the questionnaire.
    ScriptEvent answer = event(1, ScriptEvent::Key::PointAnswer);
    answer.value = 4;
    ScriptPlayer p({answer, event(2, ScriptEvent::Key::Next, true)});
    ScriptClock clock;
    clock.question_up = true;
    clock.questionnaire_up = true;
    clock.frame = 1;
    CHECK(p.take(clock).point_answer == 4);
    clock.question_up = false;  // the click is in flight; the item is still up
    for (clock.frame = 2; clock.frame < 8; ++clock.frame) CHECK_FALSE(p.take(clock).next);
    clock.questionnaire_up = false;  // answered: the next trial's ready screen is up
    CHECK(p.take(clock).next);
}
