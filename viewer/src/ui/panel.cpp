// viewer/src/ui/panel.cpp: the ImGui windows of the desktop mirror.
#include "ui/panel.hpp"  // glad first (render/gl.hpp)
#include "ui/panel_layout.hpp"

#include <imgui.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <string>

#include <core/scene.hpp>
#include <io/cloud_info.hpp>

namespace viewer {

std::string pointsDrawnText(const PanelView& v) {
    const std::string budget = v.point_budget ? std::to_string(v.point_budget) : "unlimited";
    return "points drawn per eye " + std::to_string(v.points_drawn) + " / " + std::to_string(v.points_uploaded) +
           " (budget " + budget + ", " + std::to_string(v.cells) + " cells)";
}

namespace {

// The settings panel's folding sections: display and tools.
bool drawSettingsSections(const PanelView& v) {
    bool reset = false;
    if (ImGui::CollapsingHeader("display")) {
        ImGui::SliderFloat("point size (px)", &v.style->point_size_px, 1.0f, 16.0f, "%.1f");
        ImGui::Checkbox("attenuate with distance", &v.style->attenuate);
        ImGui::Checkbox("eye-dome lighting", &v.style->eye_dome);
        if (v.style->eye_dome) ImGui::SliderFloat("EDL strength", &v.style->edl_strength, 0.1f, 4.0f, "%.2f");
        int rasterizer = static_cast<int>(v.style->rasterizer);
        if (ImGui::Combo("rasterizer", &rasterizer, "GL_POINTS\0compute\0"))
            v.style->rasterizer = static_cast<Rasterizer>(rasterizer);
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
    return reset;
}

// A source with a cache (COPC): its tree, its RAM cache and the GPU arena, in short lines.
void drawSourceLines(const PanelView& v) {
    constexpr double kMiB = 1048576.0;
    const SourceStats& c = *v.source;
    ImGui::Text("tree %zu nodes, %zu pages read, %.1f MiB", c.nodes, c.pages_read, c.hierarchy_bytes / kMiB);
    ImGui::Text("cache %.1f / %.1f MiB (peak %.1f)", c.resident_bytes / kMiB, c.cache_bytes / kMiB,
                c.resident_bytes_peak / kMiB);
    ImGui::Text("GPU %.1f / %.1f MiB (peak %.1f)", v.arena.bytes / kMiB, v.arena.bytes_bound / kMiB,
                v.arena.bytes_peak / kMiB);
    ImGui::Text("nodes %zu in RAM, %zu on GPU (+%zu -%zu)", c.nodes_resident, v.arena.nodes, v.arena.frame_nodes_added,
                v.arena.frame_nodes_evicted);
}

}  // namespace

bool drawSettingsPanel(const PanelView& v) {
    // Bottom left, in the lower half and inside the window (settingsPanelLayout): off the
    // mode plate and, on a small mirror, off most of the view; its lines wrap, not cut.
    const ImVec2 display = ImGui::GetIO().DisplaySize;
    const SettingsPanelLayout layout = settingsPanelLayout(int(display.x), int(display.y));
    ImGui::SetNextWindowPos(ImVec2(layout.x, layout.y), ImGuiCond_Always, ImVec2(0.0f, 1.0f));
    ImGui::SetNextWindowSizeConstraints(ImVec2(0.0f, 0.0f), ImVec2(layout.max_w, layout.max_h));
    ImGui::SetNextWindowBgAlpha(0.75f);
    if (layout.compact) {  // tighter rows, so the few lines fit the small panel
        ImGui::PushStyleVar(ImGuiStyleVar_WindowPadding, ImVec2(4.0f, 3.0f));
        ImGui::PushStyleVar(ImGuiStyleVar_FramePadding, ImVec2(3.0f, 1.0f));
        ImGui::PushStyleVar(ImGuiStyleVar_ItemSpacing, ImVec2(4.0f, 2.0f));
    }
    // Compact: its lines fit without a scrollbar, which would only take their room.
    ImGui::Begin("ladarvr view", nullptr,
                 ImGuiWindowFlags_AlwaysAutoResize | (layout.compact ? ImGuiWindowFlags_NoScrollbar : 0));
    ImGui::SetWindowFontScale(layout.font_scale);
    ImGui::PushTextWrapPos(layout.max_w - ImGui::GetStyle().WindowPadding.x);
    if (!v.trial.empty()) ImGui::TextUnformatted(v.trial.c_str());
    if (!layout.compact) {  // a small mirror keeps the mode to its plate
        ImGui::Text("Mode: %s  (space / controller button)", modeName(v.mode));
        if (!v.xr_state.empty())
            ImGui::Text("OpenXR: %s", v.xr_state.c_str());
        else
            ImGui::Text("Desktop mode (drag: look, WASD/QE: move in free mode)");
    } else if (!v.xr_state.empty()) {
        ImGui::Text("OpenXR: %s", v.xr_state.c_str());
    }
    if (!v.units.empty()) ImGui::Text("Units: %s", v.units.c_str());
    int colour = static_cast<int>(v.style->colour);
    // Compact: the combo alone, as wide as its longest name (C still cycles it).
    if (layout.compact)
        ImGui::SetNextItemWidth(ImGui::CalcTextSize("ground truth (target red)").x + 2.0f * ImGui::GetFrameHeight());
    if (ImGui::Combo(layout.compact ? "##colours" : "colours (C)", &colour,
                     "file colours\0height jet\0white\0ground truth (target red)\0height above ground\0"
                     "class (ASPRS)\0intensity\0return number\0"))
        v.style->colour = static_cast<ColourMode>(colour);
    if (!v.colour_note.empty()) ImGui::TextUnformatted(v.colour_note.c_str());
    // The rest folds away, so the panel stays small over the cloud.
    const bool reset = drawSettingsSections(v);
    if (!v.designation.empty()) ImGui::TextUnformatted(v.designation.c_str());
    if (layout.compact) {
        ImGui::Text("%.0f ms, %zu pts%s", v.frame_ms, v.points_drawn, v.loading ? " (loading)" : "");
    } else {
        ImGui::Text("picking: %s (last pick %.3f ms)", v.picking_ready ? "ready" : "indexing the cloud", v.pick_ms);
        ImGui::Text("frame %.2f ms (%.0f Hz)", v.frame_ms, v.frame_ms > 0 ? 1000.0 / v.frame_ms : 0.0);
        ImGui::Text("points %zu on GPU / %zu read%s", v.points_uploaded, v.points_arrived,
                    v.loading ? " (loading)" : "");
        ImGui::TextUnformatted(pointsDrawnText(v).c_str());
        if (v.source) drawSourceLines(v);
    }
    ImGui::PopTextWrapPos();
    ImGui::End();
    if (layout.compact) ImGui::PopStyleVar(3);
    return reset;
}

std::string colourNote(ColourMode wanted, const ColourSources& cloud, bool terrain_coming, bool terrain_failed) {
    if (shownColourMode(wanted, cloud) == wanted) return {};
    switch (wanted) {
        case ColourMode::AboveGround:
            return terrain_coming && !terrain_failed ? "above-ground: waiting for the terrain"
                                                     : "above-ground: no terrain; showing heights";
        case ColourMode::File: return "file: no colours in this cloud; showing heights";
        // A cloud with heights above ground has its intensities and returns in the file, but
        // its points' one float on the GPU holds the heights (docs/viewer.md, "On the GPU").
        case ColourMode::Intensity:
            return cloud.intensity && cloud.height_above_ground
                       ? "intensity: not drawn beside heights above ground; showing heights"
                       : "intensity: not in this cloud; showing heights";
        case ColourMode::Return:
            return cloud.returns && cloud.height_above_ground
                       ? "return: not drawn beside heights above ground; showing heights"
                       : "return: not in this cloud; showing heights";
        default: return {};
    }
}

std::array<std::string, 3> pickPanelLines(const PickHit& hit, const glm::dvec3& origin, const glm::dvec3& head_local,
                                          const PanelView& v) {
    const glm::dvec3 w = hit.local + origin;
    std::array<char, 160> lines[3];
    std::snprintf(lines[0].data(), lines[0].size(), "%.2f %.2f %.2f %s", w.x, w.y, w.z, v.length_unit.c_str());
    const std::string what =
        hit.asprs_class ? "class " + std::to_string(*hit.asprs_class) + " " + io::asprsClassName(*hit.asprs_class, 4)
                        : std::string(core::roleName(hit.label));
    std::snprintf(lines[1].data(), lines[1].size(), "range %.1f %s  %s", glm::length(hit.local - head_local),
                  v.length_unit.c_str(), what.c_str());
    std::snprintf(lines[2].data(), lines[2].size(), "height %.2f %s", double(hit.height_above_ground_m),
                  v.height_unit.c_str());
    return {lines[0].data(), lines[1].data(), lines[2].data()};
}

void drawPickPanel(float x, float y, const PickHit& hit, const glm::dvec3& origin, const glm::dvec3& head_local,
                   bool has_height, bool corner, const PanelView& v) {
    const std::array<std::string, 3> lines = pickPanelLines(hit, origin, head_local, v);
    const int count = has_height ? 3 : 2;
    // Its size before it is drawn, so it can be placed beside the point and inside the window.
    const ImGuiStyle& style = ImGui::GetStyle();
    float text_w = 0.0f;
    for (int i = 0; i < count; ++i) text_w = std::max(text_w, ImGui::CalcTextSize(lines[i].data()).x);
    const float panel_w = text_w + 2.0f * style.WindowPadding.x;
    const float panel_h = float(count) * ImGui::GetTextLineHeightWithSpacing() + 2.0f * style.WindowPadding.y;
    const ImVec2 display = ImGui::GetIO().DisplaySize;
    const PanelPosition at = corner ? PanelPosition{display.x - panel_w - 10.0f, display.y - panel_h - 10.0f}
                                    : pickPanelPosition(x, y, panel_w, panel_h, int(display.x), int(display.y));
    ImGui::SetNextWindowPos(ImVec2(std::max(at.x, 0.0f), std::max(at.y, 0.0f)), ImGuiCond_Always);
    ImGui::SetNextWindowBgAlpha(0.6f);
    ImGui::Begin("picked point", nullptr,
                 ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoInputs |
                     ImGuiWindowFlags_NoFocusOnAppearing | ImGuiWindowFlags_NoNav);
    for (int i = 0; i < count; ++i) ImGui::TextUnformatted(lines[i].data());
    ImGui::End();
}

void drawReadyScreen(int trial, int trials, const std::string& name, bool loaded, double time_limit_s,
                     double break_left_s) {
    const ImVec2 size = ImGui::GetIO().DisplaySize;
    ImGui::SetNextWindowPos(ImVec2(size.x * 0.5f, size.y * 0.5f), ImGuiCond_Always, ImVec2(0.5f, 0.5f));
    ImGui::SetNextWindowBgAlpha(0.9f);
    ImGui::Begin("ready", nullptr, ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_AlwaysAutoResize);
    ImGui::Text("Trial %d of %d: %s", trial + 1, trials, name.c_str());
    if (time_limit_s > 0) ImGui::Text("Time limit: %.0f s", time_limit_s);
    ImGui::Text("Find the target, point at it, designate it and confirm;");
    ImGui::Text("declare 'no target' if there is none.");
    if (break_left_s > 0.0)
        ImGui::Text("Break: please rest, %.0f s left.", std::ceil(break_left_s));
    else if (loaded)
        ImGui::Text("Ready: press the trigger or Enter to start.");
    else
        ImGui::Text("Loading the cloud...");
    ImGui::End();
}

bool drawFramePanels(PanelView v, const PanelFrame& p, int fb_w, int fb_h, EyeTarget* headset_target) {
    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    if (p.panel_pointer) {
        // After the GLFW backend's own events, so the pointer's position wins this frame; a
        // press and release queued together reach ImGui on two frames (its input trickling),
        // which is a click on what the pointer is over.
        ImGuiIO& io = ImGui::GetIO();
        io.AddMousePosEvent(float(p.panel_pointer->x) * io.DisplaySize.x, float(p.panel_pointer->y) * io.DisplaySize.y);
        if (p.panel_click) {
            io.AddMouseButtonEvent(ImGuiMouseButton_Left, true);
            io.AddMouseButtonEvent(ImGuiMouseButton_Left, false);
        }
    }
    ImGui::NewFrame();
    if (p.trial >= 0) {
        char text[256];
        std::snprintf(text, sizeof text, "trial %d of %d: %s, %.1f s", p.trial + 1, p.trials, p.trial_name.c_str(),
                      p.trial_s);
        v.trial = text;
    }
    if (p.designated_local) {
        const glm::dvec3 w = *p.designated_local + p.origin;
        char text[160];
        std::snprintf(text, sizeof text, "designated %.2f %.2f %.2f (Enter / confirm button to confirm)", w.x, w.y,
                      w.z);
        v.designation = text;
    }
    const bool reset_zoom = drawSettingsPanel(v);
    const bool asking = p.questionnaire && p.questionnaire->active();
    if (asking) {
        std::optional<Answer> a = p.questionnaire->draw(p.headset, p.panel_pointer);
        if (a && p.answered) *p.answered = std::move(a);
    } else if (p.ready_screen)
        drawReadyScreen(p.trial, p.trials, p.trial_name, p.ready_to_start, p.time_limit_s, p.break_left_s);
    // The picked point's panel beside the dot (desktop: where the dot is on screen).
    if (p.hit && !p.headset && fb_w > 0 && fb_h > 0 && !p.ready_screen && !asking) {
        const glm::dvec4 clip = p.view_projection * glm::dvec4(p.hit->local, 1.0);
        if (clip.w > 0.0) {
            const ImVec2 size = ImGui::GetIO().DisplaySize;
            const float sx = float((clip.x / clip.w * 0.5 + 0.5) * size.x);
            const float sy = float((0.5 - clip.y / clip.w * 0.5) * size.y);
            drawPickPanel(sx, sy, *p.hit, p.origin, p.head_local, p.has_height, false, v);
        }
    } else if (p.hit && p.headset && !asking) {  // the headset's panel: its bottom right corner
        drawPickPanel(0.0f, 0.0f, *p.hit, p.origin, p.head_local, p.has_height, true, v);
    }
    ImGui::Render();
    if (headset_target && fb_w > 0 && fb_h > 0 && headset_target->ensure(fb_w, fb_h)) {
        // The same windows into a texture for the headset's quad (shown from the next frame).
        glBindFramebuffer(GL_FRAMEBUFFER, headset_target->fbo);
        glViewport(0, 0, fb_w, fb_h);
        glClearColor(0.0f, 0.0f, 0.0f, 0.0f);
        glClear(GL_COLOR_BUFFER_BIT);
        ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    }
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glViewport(0, 0, fb_w, fb_h);
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    return reset_zoom;
}

}  // namespace viewer
