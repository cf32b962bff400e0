// viewer/src/ui/panel.hpp: the ImGui windows on the desktop mirror: the settings panel, the
// picked point's panel beside it, and a trial's ready screen.
#pragma once
#include "points/point_renderer.hpp"
#include "ui/questionnaire_screen.hpp"

#include <viewer/pick_index.hpp>
#include <viewer/viewer.hpp>

#include <array>
#include <optional>
#include <string>

namespace viewer {

/// What the settings panel shows and edits.
struct PanelView {
    ViewStyle* style = nullptr;
    ViewMode mode = ViewMode::Automatic;
    std::string xr_state;                              // empty: desktop mode
    std::string units;                                 // ViewerOptions::units; empty: not shown
    std::string length_unit = "m", height_unit = "m";  // ViewerOptions' symbols, for the pick panel
    double frame_ms = 0.0;
    // points_drawn: per eye (the most one eye drew), the figure the budget bounds.
    std::size_t points_uploaded = 0, points_arrived = 0, points_drawn = 0, cells = 0, point_budget = 0;
    bool loading = false;
    bool picking_ready = false;
    double pick_ms = 0.0;
    double scale = 1.0;
    bool* cut_enabled = nullptr;
    double* cut_radius_m = nullptr;
    bool* highlight_candidates = nullptr;
    std::size_t candidates = 0;
    bool* snap_turn = nullptr;
    bool* vignette = nullptr;
    bool* headset_panel = nullptr;      // null: no headset
    std::string trial;                  // "trial 2 of 5: name, 12.3 s" or empty
    std::string designation;            // "designated (x, y, z)" or empty
    ArenaStats arena;                   // the GPU arena
    std::optional<SourceStats> source;  // a source with a cache: its hierarchy and cache
    std::string colour_note;            // colourNote's line under the colour modes, or empty
};

/// Why the colours shown are not the mode chosen, for a line under the colour modes
/// ("above-ground: waiting for the terrain" while a terrain is coming); empty when they are.
std::string colourNote(ColourMode wanted, const ColourSources& cloud, bool terrain_coming, bool terrain_failed);

/// The settings panel (bottom left, settingsPanelLayout). Returns true when the zoom reset button was pressed.
bool drawSettingsPanel(const PanelView& v);
/// The settings panel's line of points drawn: per eye, against the points on the GPU (one
/// copy of the cloud, which each eye draws from), the same on the desktop and the headset.
std::string pointsDrawnText(const PanelView& v);

/// The picked point: world position, range from the head, label and height above ground,
/// in a small window beside the dot at (x, y) window pixels (pickPanelPosition: off the
/// point, inside the window), or in the window's bottom right corner with `corner`.
void drawPickPanel(float x, float y, const PickHit& hit, const glm::dvec3& origin, const glm::dvec3& head_local,
                   bool has_height, bool corner, const PanelView& v);
/// The picked point's three lines: world position and range in v.length_unit, the label,
/// and the height above ground in v.height_unit.
std::array<std::string, 3> pickPanelLines(const PickHit& hit, const glm::dvec3& origin, const glm::dvec3& head_local,
                                          const PanelView& v);

/// A trial's ready screen (centred): its name, and either "loading" or how to start.
/// `break_left_s` > 0: a break, "Break: N s left" instead of how to start.
void drawReadyScreen(int trial, int trials, const std::string& name, bool loaded, double time_limit_s,
                     double break_left_s);

/// The rest of what a frame's panels show.
struct PanelFrame {
    glm::dvec3 origin{0.0};      // world coordinates of the local frame
    bool has_height = false;     // the cloud has heights above ground
    int trial = -1, trials = 1;  // trial -1: a plain run
    std::string trial_name;
    double trial_s = 0.0, time_limit_s = 0.0;
    bool ready_screen = false, ready_to_start = false;
    double break_left_s = 0.0;  // the ready screen's break still to run
    std::optional<glm::dvec3> designated_local;
    std::optional<PickHit> hit;
    bool headset = false;  // an OpenXR session exists
    glm::dvec3 head_local{0.0};
    glm::dmat4 view_projection{1.0};  // the desktop view (where the hit's panel goes)
    /// A questionnaire item up (instead of the ready screen), and where its answer goes.
    QuestionnaireScreen* questionnaire = nullptr;
    std::optional<Answer>* answered = nullptr;
    /// The controller's pointer on the headset panel (0..1 from its top left) and whether
    /// its trigger went down this frame: a mouse move and click in the panel's windows.
    std::optional<glm::dvec2> panel_pointer;
    bool panel_click = false;
};

/// One ImGui frame: the settings panel, the ready screen or a questionnaire item, the
/// picked point's panel; drawn
/// into the window's back buffer and, with `headset_target`, into that texture for the
/// headset's quad. Returns true when the zoom reset button was pressed.
bool drawFramePanels(PanelView v, const PanelFrame& p, int fb_w, int fb_h, EyeTarget* headset_target);

}  // namespace viewer
