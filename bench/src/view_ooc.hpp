// bench/src/view_ooc.hpp: `ladarvr bench view --paths ooc`: the viewer out of core. COPC
// files of the demo scene made by the generator (sim::generateToFile, as `generate --out
// X.copc.laz` writes them) are viewed along scripted head paths by the viewer's offscreen
// stereo drawing following a viewer::CopcSource, against today's in-core path (the whole
// file streamed through a CloudFeed) on the same file and path in the same run; and the
// node selection alone on a synthetic tree of 10^5 nodes, on one core.
#pragma once
#include <cstddef>
#include <cstdio>
#include <string>
#include <vector>

namespace bench {

struct OocBenchOptions {
    std::vector<std::size_t> points = {10000000};  // cloud sizes (the generator's resolution is chosen to reach them)
    std::string head_paths = "orbit,fly-in,turn";  // any of orbit, fly-in, turn
    std::size_t point_budget = 3000000;            // per eye, as `view --point-budget`
    double cache_mb = 1024.0;                      // CopcSource's RAM cache, as `view --cache-mb`
    double gpu_mb = 2048.0;                        // the renderer's GPU arena, as `view --gpu-mb`
    std::size_t upload_points = std::size_t(1) << 18;  // per frame, as `view --upload-budget`
    int eye_width = 1440, eye_height = 1600;
    std::string rasterizer = "points";  // as `view --rasterizer`
    bool subgroup = true;               // compute: the subgroup reduction where the GPU has it (--subgroup on|off)
    std::size_t in_core_max_points = 20000000;  // the in-core baseline only up to this size
    int still_frames_max = 600;                 // frames held still waiting for full detail
    bool synthetic = false;  // synthetic surveys written node by node (synthetic_survey.hpp), not the generator's
    std::string dir;         // where the COPC files are made and kept (reused); empty: a temporary folder
    std::size_t selection_nodes = 100000;  // the synthetic tree of the selection-only rows
    std::string md;                        // markdown file whose ooc section is rewritten; empty: none
    std::string frame_log;  // folder for each run's second-lap frames as CSV (where the slow frames are); empty: none
};

/// Runs the out-of-core measurements and prints their tables (markdown) to `out`.
/// Throws core::Error("bench view: ...") on bad options or a failed run.
void runOocBench(const OocBenchOptions& options, std::FILE* out);

}  // namespace bench
