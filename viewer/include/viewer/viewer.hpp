// viewer/viewer.hpp: `ladarvr view`, the immersive viewer of paper §IV-A.
//
// A GLFW window is the desktop mirror (OpenGL 4.5 core). When an OpenXR runtime with an
// HMD is present, an OpenXR session renders both eyes every frame into per-eye swapchains
// and the mirror shows the left, right or both eye images; without one, the window is a
// desktop viewer with a mouse-and-keyboard camera. Two modes (automatic orbit / free),
// switched with the space bar or a controller button. See docs/viewer.md.
#pragma once
#include <viewer/mode_controller.hpp>
#include <viewer/cloud_feed.hpp>
#include <viewer/pick_index.hpp>
#include <viewer/point_source.hpp>
#include <viewer/script.hpp>
#include <viewer/trial.hpp>
#include <viewer/terrain_feed.hpp>

#include <core/candidates.hpp>

#include <cstddef>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace viewer {

enum class MirrorEyes { Left, Right, Both };
enum class ColourMode { File, HeightJet, White, Label, AboveGround, Class, Intensity, Return };
/// How points reach the eye images: GL_POINTS through the graphics pipeline, or two compute
/// passes (nearest depth by atomic minimum, then the colour of the nearest point) whose result
/// is copied into the same colour and depth targets. Both give the same picture; which is
/// faster depends on the GPU (docs/viewer.md).
enum class Rasterizer { Points, Compute };

/// "left" / "right" / "both"; throws core::Error("view: --mirror 'x' is not one of left, right, both").
MirrorEyes parseMirrorEyes(const std::string& name);
/// "file" / "height" / "white" / "label" / "above-ground" / "class" / "intensity" / "return";
/// throws core::Error("view: --colour 'x' is not one of ...").
/// "label" shows the ground truth: target red, environment grey, ground dark grey.
/// "above-ground" colours by height above the ground (a terrain handed in through
/// ViewerOptions::terrain, else the points' own heights above the terrain fitted by
/// `generate --ground smrf|csf`), the jet over [0, the cloud's highest], ground left white.
/// "class" shows the ASPRS classes' palette, "intensity" a grey stretch of the intensities,
/// "return" single, first, intermediate and last returns each in their colour (docs/viewer.md).
ColourMode parseColourMode(const std::string& name);
const char* colourModeName(ColourMode mode);

/// What a cloud on screen can be coloured by beyond its positions and labels.
struct ColourSources {
    bool height_above_ground = false;  // its points carry heights above a fitted terrain
    bool terrain = false;              // a terrain is bound (ViewerOptions::terrain)
    bool intensity = false;            // intensities, on a cloud without heights above ground
    bool returns = false;              // return numbers, likewise
    bool rgb = true;                   // colours of its own (a survey's file may have none), or a cloud we generated
};
/// The mode drawn for `wanted`: above-ground without a terrain or heights, file, intensity
/// or return on a cloud that does not carry them, show the height colours; the others as
/// they are.
ColourMode shownColourMode(ColourMode wanted, const ColourSources& cloud);
/// "points" / "compute"; throws core::Error("view: --rasterizer 'x' is not one of points, compute").
Rasterizer parseRasterizer(const std::string& name);
const char* rasterizerName(Rasterizer rasterizer);

/// How points look; the ImGui panel edits it live.
struct ViewStyle {
    float point_size_px = 2.0f;  // pixel size, or the size at 100 m when attenuated
    bool attenuate = false;      // size falls off with distance (size_px * 100 m / d)
    ColourMode colour = ColourMode::File;
    bool eye_dome = true;  // eye-dome lighting (Potree / CloudCompare style)
    float edl_strength = 1.0f;
    int jet_entries = 64;  // the paper's 64-entry jet map (§III-C)
    Rasterizer rasterizer = Rasterizer::Points;
};

struct ViewerOptions {
    bool use_xr = true;  // false: --no-xr, desktop mode only
    MirrorEyes mirror = MirrorEyes::Both;
    int window_width = 1280, window_height = 720;
    bool hidden_window = false;  // open the window unmapped (nothing shown on the desktop)
    long frames = 0;  // stop after N frames (XR: submitted; above-ground colours: and their terrain), 0 = until closed
    double timeout_s = 0.0;  // stop with an error after this long (0 = never)
    std::vector<ScriptEvent> script;
    std::filesystem::path screenshot;  // PNG of the mirror at the last frame
    std::filesystem::path log_json;    // machine-readable run log
    std::string units;  // the units of the cloud's coordinates, as its CRS says, for the panel; empty: not shown
    /// The symbols the pick panel gives its coordinates and ranges (horizontal) and heights
    /// (vertical) in: the cloud's own units, as its CRS says.
    std::string length_unit = "m", height_unit = "m";
    /// Metres per unit of the cloud's heights, as its CRS says (1: none stated): the
    /// colour ranges' stray returns are parted by gaps given in metres.
    double height_unit_m = 1.0;
    ViewStyle style;
    ModeOptions modes;
    std::size_t upload_points_per_frame = 1u << 18;  // streaming budget per frame
    /// Points drawn per eye and frame at most (LOD prefixes by screen importance);
    /// 0 = unlimited. 3 M keeps the paper's 1.6 M point cloud whole.
    std::size_t point_budget = 3000000;
    bool cull = true;         // skip cells outside the eyes' frusta
    bool vsync = true;        // desktop mode swap interval 1 (off in --frames runs)
    bool gpu_timing = false;  // GL timer query per frame, logged as gpu_ms (waits for the GPU)
    bool quiet = false;
    PickOptions pick;                         // the pointer's cone (--pick-angle)
    double cut_radius_m = 15.0;               // the cutting volume's radius when switched on (V / controller)
    bool cut_enabled = false;                 // the cutting volume on from the start (around the designation)
    std::vector<core::Candidate> candidates;  // --candidates: boxes to confirm or reject
    // Comfort in free mode, in the headset (docs/viewer.md).
    bool snap_turn = true;              // thumbstick turns in steps, not smoothly
    double snap_turn_deg = 45.0;        // step
    double snap_turn_debounce_s = 0.5;  // at most one step per this long
    bool vignette = true;               // darken the edges of the view while moving
    double vignette_aperture = 0.7;     // radius of the clear centre (fraction of the half view)
    double vignette_feather = 0.2;      // width of the fade to black
    bool headset_panel = true;          // the ImGui panel on a quad in the headset (below the gaze)
    /// A recorded trace to replay in the mirror (desktop only): once the cloud has loaded,
    /// the view follows the trace's head poses, zoom and mode in real time, its pointer hit
    /// shown as a dot, and the run ends after its last sample (exit "replay done").
    std::vector<TraceSample> replay;
    /// The replayed trial's marks (designations, verdicts), shown as their times come.
    std::vector<TrialMark> replay_marks;
    // Out of core (docs/viewer.md "Large clouds").
    /// Bytes the points' GPU buffers take at most (--gpu-mb): nodes the view no longer wants
    /// leave the GPU, least recently drawn first, to make room for those it wants.
    std::size_t gpu_bytes = std::size_t(2048) << 20;
    /// Bytes uploaded to the GPU per frame at most (--upload-mb); 0: upload_points_per_frame counts.
    std::size_t upload_bytes_per_frame = 0;
    /// Choose point_budget from the GPU class (GL_RENDERER / GL_VENDOR, point_budget.hpp)
    /// instead: `view` sets it when no --point-budget is given.
    bool point_budget_auto = false;
    /// Choose style.rasterizer from the GPU class instead (computeRasterizerByDefault):
    /// `view` sets it when no --rasterizer is given.
    bool rasterizer_auto = false;
    /// Lower the point budget while frames run late, raise it again up to point_budget
    /// (--adaptive-budget; `view` turns it on for interactive runs, off with --frames).
    bool adaptive_budget = false;
    /// Choose the automatic point budget and rasterizer from the first frames' times
    /// instead of the GPU class (point_budget.hpp's BudgetMeasure), remembered per GPU in
    /// the cache folder (--measure-budget; `view` turns it on for interactive runs).
    bool measure_budget = false;
    /// The ground under the cloud, when it comes from elsewhere than the points' own
    /// heights above ground (terrain_feed.hpp): the file's class 2, or a terrain fitted in
    /// the background. Null: none.
    std::shared_ptr<TerrainFeed> terrain;
};

/// Throws core::Error("view: ...") for values out of range.
void validate(const ViewerOptions& o);

/// Runs the viewer until the window closes, Escape, SIGINT / SIGTERM (the frame finishes
/// and the log is written) or `frames` frames. Returns 0 on a clean run, 1 on a timeout or
/// a failed screenshot/log, 128 + the signal's number when stopped by one. Throws core::Error only during
/// setup (no window could be opened, shaders failed); the frame loop never throws.
int runViewer(const ViewerOptions& options, CloudFeed& feed);
/// runViewer that also hands back the run log (the --log-json document) in `log_json`.
int runViewer(const ViewerOptions& options, CloudFeed& feed, std::string& log_json);

/// runViewer over a point source that holds nodes by choice (a COPC file, copc_source.hpp)
/// instead of a streamed feed.
int runViewer(const ViewerOptions& options, PointSource& source);

/// Runs `source`'s trials one after another in one window and one XR session
/// (viewer/trial.hpp: a ready screen per trial, automatic mode at its start, ends on
/// confirm, no target, its time limit or quit), reporting to `observer` as it goes.
/// SIGINT / SIGTERM end the run like Escape: the frame finishes, the trial in flight is
/// reported as quit, the session ends. Returns 0 when every trial ran, 1 on a load error
/// or a failed log, 128 + the signal's number when stopped by one. Throws like runViewer.
int runTrials(const ViewerOptions& options, TrialSource& source, TrialObserver& observer);

}  // namespace viewer
