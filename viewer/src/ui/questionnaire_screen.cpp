// viewer/src/ui/questionnaire_screen.cpp: the questionnaire items' window and answer checks.
#include "ui/questionnaire_screen.hpp"

#include <imgui.h>

#include <algorithm>
#include <charconv>
#include <cstring>

namespace viewer {

void QuestionnaireScreen::start(int gap, std::vector<Question> questions) {
    gap_ = gap;
    questions_ = std::move(questions);
    index_ = 0;
    selected_.reset();
    text_.clear();
    focus_text_ = true;
    buttons_.clear();
    shown_ = false;
}

std::optional<glm::dvec2> QuestionnaireScreen::buttonCentre(int value) const {
    for (const auto& [v, centre] : buttons_)
        if (v == value) return centre;
    return std::nullopt;
}

std::string QuestionnaireScreen::check(const Answer& a) const {
    if (!active()) return "no questionnaire item is up";
    const Question& q = current();
    const std::string& r = a.response;
    if (q.free_text) {
        if (a.skipped) return r.empty() ? "" : "a skipped item has no text";
        if (r.empty() || r.size() > kMaxAnswerBytes)
            return "a text of 1 to " + std::to_string(kMaxAnswerBytes) + " bytes is needed, not " +
                   std::to_string(r.size());
        if (std::any_of(r.begin(), r.end(), [](char c) { return (unsigned char)c < 0x20 || c == 0x7f; }))
            return "the text holds a control character";
        return "";
    }
    int v = 0;
    const auto [ptr, ec] = std::from_chars(r.data(), r.data() + r.size(), v);
    if (a.skipped || r.empty() || ec != std::errc() || ptr != r.data() + r.size() || v < q.min || v > q.max ||
        (v - q.min) % q.step != 0)
        return "allowed a whole number from " + std::to_string(q.min) + " to " + std::to_string(q.max) +
               (q.step > 1 ? " in steps of " + std::to_string(q.step) : "");
    return "";
}

std::optional<Answer> QuestionnaireScreen::draw(bool headset, const std::optional<glm::dvec2>& pointer) {
    if (!active()) return std::nullopt;
    const Question& q = current();
    std::optional<Answer> out;
    const ImVec2 size = ImGui::GetIO().DisplaySize;
    ImGui::SetNextWindowPos(ImVec2(size.x * 0.5f, size.y * 0.5f), ImGuiCond_Always, ImVec2(0.5f, 0.5f));
    ImGui::SetNextWindowSize(ImVec2(std::min(size.x * 0.9f, 900.0f), 0.0f), ImGuiCond_Always);
    ImGui::SetNextWindowBgAlpha(0.95f);
    ImGui::Begin("questionnaire", nullptr, ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_NoSavedSettings);
    // A window coming back lays out once unseen (its size is fitted): its buttons have
    // their place from the next frame.
    const bool appearing = ImGui::IsWindowAppearing();
    ImGui::TextWrapped("%s", q.title.c_str());
    ImGui::Text("Item %d of %d", q.number, q.count);
    ImGui::Separator();
    ImGui::TextWrapped("%s", q.text.c_str());
    ImGui::Spacing();
    if (q.free_text) {
        if (headset) {
            ImGui::TextWrapped("(answered at the desktop only: skipped in the headset)");
        } else {
            char buffer[kMaxAnswerBytes + 1] = {};
            std::memcpy(buffer, text_.data(), std::min(text_.size(), kMaxAnswerBytes));
            ImGui::SetNextItemWidth(-1.0f);
            if (focus_text_) ImGui::SetKeyboardFocusHere();
            focus_text_ = false;
            const bool entered =
                ImGui::InputText("##answer", buffer, sizeof buffer, ImGuiInputTextFlags_EnterReturnsTrue);
            text_ = buffer;
            if ((ImGui::Button("Submit") || entered) && !text_.empty()) out = Answer{text_, false};
        }
    } else {
        // One button per rating; the arrow keys move a highlight and Enter answers with it.
        const int n = (q.max - q.min) / q.step + 1;
        if (ImGui::IsKeyPressed(ImGuiKey_RightArrow))
            selected_ = selected_ ? std::min(*selected_ + q.step, q.max) : q.min + (n / 2) * q.step;
        if (ImGui::IsKeyPressed(ImGuiKey_LeftArrow))
            selected_ = selected_ ? std::max(*selected_ - q.step, q.min) : q.min + (n / 2) * q.step;
        const float avail = ImGui::GetContentRegionAvail().x;
        const float spacing = ImGui::GetStyle().ItemSpacing.x;
        const float width = std::max(24.0f, (avail - spacing * float(n - 1)) / float(n));
        if (!appearing) buttons_.clear();
        for (int k = 0; k < n; ++k) {
            const int v = q.min + k * q.step;
            const std::string label =
                (static_cast<std::size_t>(k) < q.labels.size() ? std::to_string(v) + " " + q.labels[std::size_t(k)]
                                                               : std::to_string(v)) +
                "##" + std::to_string(v);
            if (k > 0) ImGui::SameLine();
            const bool highlight = selected_ && *selected_ == v;
            if (highlight) ImGui::PushStyleColor(ImGuiCol_Button, ImVec4(0.9f, 0.6f, 0.1f, 1.0f));
            if (ImGui::Button(label.c_str(), ImVec2(width, 40.0f))) out = Answer{std::to_string(v), false};
            const ImVec2 lo = ImGui::GetItemRectMin(), hi = ImGui::GetItemRectMax();
            if (!appearing)
                buttons_.emplace_back(v, glm::dvec2(0.5 * (lo.x + hi.x) / std::max(1.0f, size.x),
                                                    0.5 * (lo.y + hi.y) / std::max(1.0f, size.y)));
            if (highlight) ImGui::PopStyleColor();
        }
        if (!q.low_label.empty() || !q.high_label.empty()) {
            ImGui::TextUnformatted(q.low_label.c_str());
            ImGui::SameLine(
                std::max(0.0f, ImGui::GetWindowContentRegionMax().x - ImGui::CalcTextSize(q.high_label.c_str()).x));
            ImGui::TextUnformatted(q.high_label.c_str());
        }
        if (selected_ && (ImGui::IsKeyPressed(ImGuiKey_Enter) || ImGui::IsKeyPressed(ImGuiKey_KeypadEnter)))
            out = Answer{std::to_string(*selected_), false};
        ImGui::TextDisabled(headset ? "Point at a rating and pull the trigger."
                                    : "Click a rating (or use the arrow keys and Enter).");
    }
    ImGui::End();
    shown_ = shown_ || !appearing;
    if (pointer)  // the controller's pointer on the panel
        ImGui::GetForegroundDrawList()->AddCircleFilled(ImVec2(float(pointer->x) * size.x, float(pointer->y) * size.y),
                                                        6.0f, IM_COL32(255, 230, 40, 255));
    return out;
}

}  // namespace viewer
