// viewer/src/options.cpp: validation of the viewer's options (their names: option_names.cpp;
// scripts: script.cpp).
#include <viewer/viewer.hpp>

#include <core/error.hpp>
#include <platform/safe_file.hpp>

#include <cmath>

namespace viewer {

void validate(const ViewerOptions& o) {
    validate(o.modes);
    auto fail = [](const std::string& what) { throw core::Error("view: " + what); };
    if (o.window_width < 64 || o.window_width > 16384 || o.window_height < 64 || o.window_height > 16384)
        fail("window size " + std::to_string(o.window_width) + "x" + std::to_string(o.window_height) +
             ": allowed 64..16384 each");
    if (o.frames < 0) fail("--frames " + std::to_string(o.frames) + ": allowed >= 0 (0 = until closed)");
    if (!(std::isfinite(o.timeout_s) && o.timeout_s >= 0.0))
        fail("--timeout " + core::shownNumber(o.timeout_s) + ": allowed a finite value >= 0");
    if (!(o.style.point_size_px >= 1.0f && o.style.point_size_px <= 64.0f))
        fail("--point-size " + core::shownNumber(o.style.point_size_px) + ": allowed [1, 64]");
    if (o.style.jet_entries < 2 || o.style.jet_entries > 256)
        fail("jet entries " + std::to_string(o.style.jet_entries) + ": allowed [2, 256]");
    if (o.upload_points_per_frame < 1024)
        fail("--upload-budget " + std::to_string(o.upload_points_per_frame) + ": allowed >= 1024 points");
    if (o.gpu_bytes < (std::size_t(1) << 14))
        fail("--gpu-mb " + core::shownNumber(double(o.gpu_bytes) / 1048576.0) + ": allowed >= 1/64 MiB");
    if (o.upload_bytes_per_frame != 0 && o.upload_bytes_per_frame < (std::size_t(1) << 14))
        fail("--upload-mb " + core::shownNumber(double(o.upload_bytes_per_frame) / 1048576.0) +
             ": allowed >= 1/64 MiB (or none: --upload-budget counts)");
    validate(o.pick);
    if (!(o.cut_radius_m >= 0.1 && o.cut_radius_m <= 10000.0))
        fail("--cut-radius " + core::shownNumber(o.cut_radius_m) + ": allowed [0.1, 10000] m");
    if (!(o.snap_turn_deg > 0.0 && o.snap_turn_deg <= 180.0))
        fail("--snap-turn-deg " + core::shownNumber(o.snap_turn_deg) + ": allowed (0, 180]");
    if (!(o.snap_turn_debounce_s >= 0.0 && o.snap_turn_debounce_s <= 10.0))
        fail("snap turn debounce " + core::shownNumber(o.snap_turn_debounce_s) + ": allowed [0, 10] s");
    if (!(o.vignette_aperture > 0.0 && o.vignette_aperture <= 1.0) ||
        !(o.vignette_feather >= 0.0 && o.vignette_feather <= 1.0))
        fail("vignette aperture " + core::shownNumber(o.vignette_aperture) + " / feather " +
             core::shownNumber(o.vignette_feather) + ": allowed (0, 1] / [0, 1]");
    if (!o.replay.empty() && o.use_xr) fail("a replay runs in the mirror only: use it with --no-xr");
    if (!o.screenshot.empty() && o.screenshot.extension() != ".png")
        fail("--screenshot " + o.screenshot.string() + ": the file name must end in .png");
}

}  // namespace viewer
