// viewer/src/ui/questionnaire_screen.hpp: a study's questionnaire items between trials, one
// at a time (viewer/trial.hpp's Question): which item is up, whether an answer fits it,
// and the ImGui window that shows it on the desktop mirror and the headset's panel
// (buttons clicked with the mouse or the controller's pointer, arrow keys and Enter, a
// text field on the desktop).
#pragma once
#include <viewer/trial.hpp>

#include <glm/vec2.hpp>

#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace viewer {

/// The longest text answer kept, in bytes.
inline constexpr std::size_t kMaxAnswerBytes = 1000;

class QuestionnaireScreen {
  public:
    /// Starts asking `questions` (at gap `gap` of the run); inactive when empty.
    void start(int gap, std::vector<Question> questions);
    bool active() const { return index_ < questions_.size(); }
    int gap() const { return gap_; }
    /// The index of the item up (into start()'s list); valid while active().
    int index() const { return static_cast<int>(index_); }
    const Question& current() const { return questions_[index_]; }
    /// The item up has been drawn (its buttons have a place).
    bool shown() const { return shown_; }

    /// Empty when `answer` fits the item up (a whole number from min to max on its step, or
    /// a text of 1 to kMaxAnswerBytes bytes without control characters; a skipped text item
    /// with no text); else why not, in one line.
    std::string check(const Answer& answer) const;
    /// The item answered: the next one comes up.
    void advance() {
        ++index_;
        selected_.reset();
        text_.clear();
        focus_text_ = true;
        buttons_.clear();
        shown_ = false;
    }

    /// The item's window (centred); returns the answer clicked or entered this frame.
    /// `headset`: a headset is in use (a text item says it is skipped there); `pointer`:
    /// where the controller's pointer meets the panel (0..1 from its top left), drawn as a dot.
    std::optional<Answer> draw(bool headset, const std::optional<glm::dvec2>& pointer);

    /// Where rating `value`'s button was drawn last (its centre, 0..1 of the display from
    /// the top left); nullopt before the item's first frame.
    std::optional<glm::dvec2> buttonCentre(int value) const;

  private:
    std::vector<std::pair<int, glm::dvec2>> buttons_;  // the item's buttons, as last drawn
    std::vector<Question> questions_;
    std::size_t index_ = 0;
    int gap_ = 0;
    std::optional<int> selected_;  // the rating the arrow keys moved to
    std::string text_;             // the text field's contents
    bool focus_text_ = true;       // a new item: its text field takes the keyboard
    bool shown_ = false;
};

}  // namespace viewer
