// viewer/viewer.hpp: `ladarvr view`, the immersive viewer of paper §IV-A.
//
// A GLFW window is the desktop mirror (OpenGL 4.5 core). When an OpenXR runtime with an
// HMD is present, an OpenXR session renders both eyes every frame into per-eye swapchains
// and the mirror shows the left, right or both eye images; without one, the window is a
// desktop viewer with a mouse-and-keyboard camera. Two modes (automatic orbit / free),
// switched with the space bar or a controller button. See docs/viewer.md.
#pragma once
#include <viewer/camera_rig.hpp>
#include <viewer/cloud_feed.hpp>

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

namespace viewer {

enum class MirrorEyes { Left, Right, Both };
enum class ColourMode { File, HeightJet, White, Label };

/// "left" / "right" / "both"; throws engine::Error("view: --mirror 'x' is not one of left, right, both").
MirrorEyes parseMirrorEyes(const std::string& name);
/// "file" / "height" / "white" / "label"; throws engine::Error("view: --colour 'x' is not one of ...").
/// "label" shows the ground truth: target red, environment grey, ground dark grey.
ColourMode parseColourMode(const std::string& name);
const char* colourModeName(ColourMode mode);

/// How points look; the ImGui panel edits it live.
struct ViewStyle {
    float point_size_px = 2.0f;        // pixel size, or the size at 100 m when attenuated
    bool attenuate = false;            // size falls off with distance (size_px * 100 m / d)
    ColourMode colour = ColourMode::File;
    bool eye_dome = true;              // eye-dome lighting (Potree / CloudCompare style)
    float edl_strength = 1.0f;
    int jet_entries = 64;              // the paper's 64-entry jet map (§III-C)
};

/// A scripted key press at a frame (for tests and demos): "<frame> <key>" lines.
struct ScriptEvent {
    long frame = 0;
    enum class Key { Space, Escape } key = Key::Space;
};
/// The largest script read (a line per key press: a megabyte is tens of thousands).
inline constexpr std::size_t kMaxScriptBytes = std::size_t(1) << 20;
/// Parses a script file: one "<frame> space|escape" per line, '#' comments, blank lines.
/// Throws engine::Error("view: --script <file> line N: ...") on a bad line, and
/// "view: --script <file>: is a directory; ..." for anything but a regular file of at
/// most kMaxScriptBytes (engine::readTextFile). Bytes of the file are shown escaped.
std::vector<ScriptEvent> readScript(const std::filesystem::path& file);

struct ViewerOptions {
    bool use_xr = true;                 // false: --no-xr, desktop mode only
    MirrorEyes mirror = MirrorEyes::Both;
    int window_width = 1280, window_height = 720;
    bool hidden_window = false;         // for benchmarks
    long frames = 0;                    // stop after N frames (XR: submitted), 0 = until closed
    double timeout_s = 0.0;             // stop with an error after this long (0 = never)
    std::vector<ScriptEvent> script;
    std::filesystem::path screenshot;   // PNG of the mirror at the last frame
    std::filesystem::path log_json;     // machine-readable run log
    ViewStyle style;
    ModeOptions modes;
    std::size_t upload_points_per_frame = 1u << 18;   // streaming budget per frame
    /// Points drawn per eye and frame at most (issue 5: LOD prefixes by screen importance);
    /// 0 = unlimited. 3 M keeps the paper's 1.6 M point cloud whole.
    std::size_t point_budget = 3000000;
    bool cull = true;                   // skip cells outside the eyes' frusta
    bool vsync = true;                  // desktop mode swap interval 1 (off in --frames runs)
    bool gpu_timing = false;            // GL timer query per frame (waits for the GPU; benchmarks)
    bool quiet = false;
};

/// Throws engine::Error("view: ...") for values out of range.
void validate(const ViewerOptions& o);

/// Runs the viewer until the window closes, Escape, or `frames` frames. Returns 0 on a
/// clean run, 1 on a timeout or a failed screenshot/log. Throws engine::Error only during
/// setup (no window could be opened, shaders failed); the frame loop never throws.
int runViewer(const ViewerOptions& options, CloudFeed& feed);
/// runViewer that also hands back the run log (the --log-json document) in `log_json`.
int runViewer(const ViewerOptions& options, CloudFeed& feed, std::string& log_json);

/// One measured configuration of `ladarvr bench view`.
struct ViewBenchResult {
    std::string path;                    // "mirror", "xr" or "stereo-egl"
    std::size_t points = 0;
    int width = 0, height = 0;           // per eye (xr, stereo-egl) or the window (mirror)
    double cpu_ms_median = 0.0;          // CPU time to record and submit the frame's draws
    double gpu_ms_median = 0.0;          // GL timer query around the frame's draws
    double frame_ms_median = 0.0;        // wall time of a whole frame (loop period / until glFinish)
    int frames = 0;                      // measured frames (after warm-up)
    /// stereo-egl only: the same eyes drawn by render::PointSplatRenderer (the metric's plain
    /// 2 px splats: no eye-dome lighting, no colour modes), the in-run baseline; 0 if not run.
    double baseline_gpu_ms_median = 0.0;
    std::string gl;                      // GL vendor / renderer / version
    std::string note;                    // why a path was skipped, or what it stands for
    std::size_t points_drawn = 0;        // per frame, both eyes (stereo-egl and skip rows)
};

struct ViewBenchOptions {
    int warmup_frames = 3;               // after every point is on the GPU
    int frames = 10;
    bool mirror = true;                  // the desktop window (needs a display)
    bool xr = true;                      // the OpenXR path (needs a runtime with an HMD)
    bool egl = true;                     // offscreen stereo through EGL (no display, any GPU)
    /// Issue 5 before/after: offscreen stereo (EGL) of the orbit view and of a view turned
    /// away from the cloud, each with nothing skipped, frustum culling only, and culling +
    /// `point_budget` (LOD), interleaved frame by frame.
    bool skip = false;
    std::size_t point_budget = 3000000;
    int eye_width = 1440, eye_height = 1600;   // stereo-egl eye size (Index / Vive Pro class)
};

/// Measures the viewer drawing `cloud` (entirely uploaded before measuring, eye-dome
/// lighting on): the real frame loop in the desktop mirror path and the OpenXR path, and
/// the same per-eye drawing in an offscreen EGL stereo loop; medians over `frames` frames
/// after warm-up. A path that cannot run here is returned with `note` saying why.
std::vector<ViewBenchResult> benchmarkViewer(const engine::PointCloud& cloud,
                                             const ViewBenchOptions& options);

}  // namespace viewer
