// viewer/src/input/script_player.hpp: a --script played back as operator input, one frame
// at a time (viewer/script.hpp has the file format).
#pragma once
#include "input/operator_input.hpp"

#include <viewer/script.hpp>

#include <cstddef>
#include <vector>

namespace viewer {

/// The frame counts a script's lines are timed against.
struct ScriptClock {
    long frame = 0;                 // frames counted so far
    long desktop_since_frame = -1;  // when the viewer dropped to desktop mode (-1: not yet)
    long loaded_since_frame = -1;   // when the whole cloud was first on the GPU (-1: not yet)
    /// A ready screen is up and cannot be dismissed yet (its cloud is loading): a `next`
    /// waits, so a script does not race the loader.
    bool ready_screen_waiting = false;
    /// A questionnaire item is on screen (drawn, no scripted click on it in flight): an
    /// `answer` or `point_answer` waits for one.
    bool question_up = false;
    long pickable_since_frame = -1;  // when the pointer could first pick (-1: not yet)
    /// A questionnaire is up (an item on screen, or a scripted click on it still going
    /// through the panel): a `next` waits for it to end, so it dismisses the ready screen
    /// that follows instead of being spent on the questionnaire.
    bool questionnaire_up = false;
};

class ScriptPlayer {
  public:
    explicit ScriptPlayer(std::vector<ScriptEvent> events) : events_(std::move(events)) {}
    /// The actions due by `clock`. An action that ends a trial or leaves a ready screen
    /// (next, confirm, no_target) or answers a question ends this frame's actions: the
    /// next ones act on what follows it.
    OperatorInput take(const ScriptClock& clock);

  private:
    std::vector<ScriptEvent> events_;
    std::size_t next_ = 0;
    long last_frame_ = 0;  // the frame the previous action ran at (for +N)
};

}  // namespace viewer
