// viewer/src/panel.cpp: the ImGui windows of the desktop mirror.
#include "panel.hpp"

#include <imgui.h>

#include <core/scene.hpp>

namespace viewer {

bool drawSettingsPanel(const PanelView& v) {
    bool reset = false;
    ImGui::SetNextWindowPos(ImVec2(10, 10), ImGuiCond_FirstUseEver);
    ImGui::SetNextWindowBgAlpha(0.75f);
    ImGui::Begin("ladarvr view", nullptr, ImGuiWindowFlags_AlwaysAutoResize);
    if (!v.trial.empty()) ImGui::TextUnformatted(v.trial.c_str());
    ImGui::Text("Mode: %s  (space / controller button)", modeName(v.mode));
    if (!v.xr_state.empty()) ImGui::Text("OpenXR: %s", v.xr_state.c_str());
    else ImGui::Text("Desktop mode (drag: look, WASD/QE: move in free mode)");
    int colour = static_cast<int>(v.style->colour);
    if (ImGui::Combo("colours (C)", &colour, "file colours\0height jet\0white\0ground truth (target red)\0height above ground\0"))
        v.style->colour = static_cast<ColourMode>(colour);
    // The rest folds away, so the panel stays small over the cloud.
    if (ImGui::CollapsingHeader("display")) {
        ImGui::SliderFloat("point size (px)", &v.style->point_size_px, 1.0f, 16.0f, "%.1f");
        ImGui::Checkbox("attenuate with distance", &v.style->attenuate);
        ImGui::Checkbox("eye-dome lighting", &v.style->eye_dome);
        if (v.style->eye_dome) ImGui::SliderFloat("EDL strength", &v.style->edl_strength, 0.1f, 4.0f, "%.2f");
    }
    if (ImGui::CollapsingHeader("tools")) {
        ImGui::Text("click: designate  Enter: confirm  Backspace: reject  N: no target");
        ImGui::Checkbox("cutting volume (V)", v.cut_enabled);
        float radius = static_cast<float>(*v.cut_radius_m);
        if (ImGui::SliderFloat("cut radius (m) [ ]", &radius, 1.0f, 200.0f, "%.1f", ImGuiSliderFlags_Logarithmic))
            *v.cut_radius_m = radius;
        if (v.candidates > 0) ImGui::Checkbox("highlight candidates", v.highlight_candidates);
        ImGui::Text("zoom x%.2f (wheel, two-hand grab)", v.scale);
        ImGui::SameLine();
        if (ImGui::Button("reset (R)")) reset = true;
        ImGui::Checkbox("snap turn", v.snap_turn);
        ImGui::SameLine();
        ImGui::Checkbox("vignette while moving", v.vignette);
        if (v.headset_panel) ImGui::Checkbox("this panel in the headset", v.headset_panel);
    }
    if (!v.designation.empty()) ImGui::TextUnformatted(v.designation.c_str());
    ImGui::Text("picking: %s (last pick %.3f ms)", v.picking_ready ? "ready" : "indexing the cloud", v.pick_ms);
    ImGui::Text("frame %.2f ms (%.0f Hz)", v.frame_ms, v.frame_ms > 0 ? 1000.0 / v.frame_ms : 0.0);
    ImGui::Text("points %zu on GPU / %zu read%s", v.points_uploaded, v.points_arrived, v.loading ? " (loading)" : "");
    ImGui::Text("points drawn %zu / %zu (budget %s per eye, %zu cells)", v.points_drawn, v.points_uploaded,
                v.point_budget ? std::to_string(v.point_budget).c_str() : "unlimited", v.cells);
    ImGui::End();
    return reset;
}

void drawPickPanel(float x, float y, const PickHit& hit, const glm::dvec3& origin, const glm::dvec3& head_local,
                   bool has_height) {
    ImGui::SetNextWindowPos(ImVec2(x + 16.0f, y + 16.0f), ImGuiCond_Always);
    ImGui::SetNextWindowBgAlpha(0.6f);
    ImGui::Begin("picked point", nullptr,
                 ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoInputs |
                     ImGuiWindowFlags_NoFocusOnAppearing | ImGuiWindowFlags_NoNav);
    const glm::dvec3 w = hit.local + origin;
    ImGui::Text("%.2f %.2f %.2f m", w.x, w.y, w.z);
    ImGui::Text("range %.1f m  %s", glm::length(hit.local - head_local), std::string(core::roleName(hit.label)).c_str());
    if (has_height) ImGui::Text("height %.2f m", double(hit.height_above_ground_m));
    ImGui::End();
}

void drawReadyScreen(int trial, int trials, const std::string& name, bool loaded, double time_limit_s) {
    const ImVec2 size = ImGui::GetIO().DisplaySize;
    ImGui::SetNextWindowPos(ImVec2(size.x * 0.5f, size.y * 0.5f), ImGuiCond_Always, ImVec2(0.5f, 0.5f));
    ImGui::SetNextWindowBgAlpha(0.9f);
    ImGui::Begin("ready", nullptr, ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_AlwaysAutoResize);
    ImGui::Text("Trial %d of %d: %s", trial + 1, trials, name.c_str());
    if (time_limit_s > 0) ImGui::Text("Time limit: %.0f s", time_limit_s);
    ImGui::Text("Find the target, point at it, designate it and confirm;");
    ImGui::Text("declare 'no target' if there is none.");
    if (loaded) ImGui::Text("Ready: press the trigger or Enter to start.");
    else ImGui::Text("Loading the cloud...");
    ImGui::End();
}

}  // namespace viewer
