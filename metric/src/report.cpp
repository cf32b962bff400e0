// metric/src/report.cpp: views.csv, summary.json and the I1..I4 PNGs, written as one set.
#include <metric/report.hpp>

#include <core/error.hpp>
#include <io/png.hpp>
#include <platform/output_folder.hpp>
#include <platform/safe_file.hpp>

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <string_view>
#include <utility>

namespace metric {
namespace {

std::string number(double v, const char* format) {
    if (std::isnan(v)) return "";
    char buffer[64];
    std::snprintf(buffer, sizeof buffer, format, v);
    return buffer;
}

nlohmann::json orNull(double v) { return std::isnan(v) ? nlohmann::json(nullptr) : nlohmann::json(v); }

}  // namespace

std::string viewsCsv(const MetricResult& r) {
    std::string csv =
        "view,eye_x,eye_y,eye_z,look_x,look_y,look_z,up_x,up_y,up_z,vfov_deg,width,height,"
        "i1,i2,i3,i4,metric,visible,exact\n";
    for (const ViewResult& v : r.views) {
        const glm::dvec3 eye = r.origin + v.pose.eye, look = r.origin + v.pose.look_at;
        csv += std::to_string(v.view);
        for (double x : {eye.x, eye.y, eye.z, look.x, look.y, look.z}) csv += "," + number(x, "%.4f");
        for (double x : {v.pose.up.x, v.pose.up.y, v.pose.up.z}) csv += "," + number(x, "%.9f");
        csv += "," + number(r.options.orbit.vfov_deg, "%.6g");
        csv += "," + std::to_string(r.options.width) + "," + std::to_string(r.options.height);
        for (std::int64_t n : {v.i1, v.i2, v.i3, v.i4}) csv += "," + std::to_string(n);
        csv += "," + number(v.metric, "%.6f") + "," + number(v.visible, "%.6f") + "," + number(v.exact, "%.6f");
        csv += "\n";
    }
    return csv;
}

std::string summaryJson(const MetricResult& r) {
    nlohmann::json j;
    j["views"] = r.views.size();
    j["views_used"] = r.views_used;
    nlohmann::json excluded = nlohmann::json::array();
    int frustum_skipped = 0;
    for (const ViewResult& v : r.views) {
        if (!v.used) excluded.push_back(v.view);
        if (v.frustum_skipped) ++frustum_skipped;
    }
    j["views_excluded"] = excluded;  // |I1| = 0: target out of frame or hidden from P1
    j["views_frustum_skipped"] = frustum_skipped;
    j["metric_mean"] = orNull(r.metric_mean);
    j["metric_min"] = orNull(r.metric_min);
    j["metric_max"] = orNull(r.metric_max);
    j["visible_mean"] = orNull(r.visible_mean);
    j["depth_visible_mean"] = orNull(r.depth_visible_mean);
    j["exact_mean"] = r.has_exact ? orNull(r.exact_mean) : nlohmann::json(nullptr);
    j["seconds"] = r.seconds;
    j["seconds_render"] = r.seconds_render;
    j["seconds_exact"] = r.seconds_exact;
    j["points_drawn"] = r.points_drawn;
    const glm::dvec3 look = r.origin + r.look_at;
    j["look_at"] = {look.x, look.y, look.z};
    j["origin"] = {r.origin.x, r.origin.y, r.origin.z};
    j["views_from"] = r.options.poses_world.empty() ? "orbit" : "poses";  // poses: e.g. an operator's trace
    const auto& o = r.options;
    j["options"] = {{"radius_m", o.orbit.radius_m},
                    {"altitude_m", o.orbit.altitude_m},
                    {"vfov_deg", o.orbit.vfov_deg},
                    {"width", o.width},
                    {"height", o.height},
                    {"splat_px", o.splat_px},
                    {"skip", o.skip},
                    {"picture_view", o.picture_view},
                    {"rasterizer", o.rasterizer == Rasterizer::Compute ? "compute" : "raster"},
                    {"depth_margin_m", o.depth_margin_m}};
    return j.dump(2) + "\n";
}

bool isReportFile(const std::string& name) {
    if (name == "views.csv" || name == "summary.json") return true;
    // view_<K>_i<1..4>.png
    constexpr std::string_view kHead = "view_", kTail = ".png";
    if (name.size() < kHead.size() + 1 + 3 + kTail.size() || name.compare(0, kHead.size(), kHead) != 0 ||
        name.compare(name.size() - kTail.size(), kTail.size(), kTail) != 0)
        return false;
    const std::string middle = name.substr(kHead.size(), name.size() - kHead.size() - kTail.size());
    const std::size_t digits = middle.find_first_not_of("0123456789");
    return digits > 0 && digits != std::string::npos && middle.size() == digits + 3 &&
           middle.compare(digits, 2, "_i") == 0 && middle[digits + 2] >= '1' && middle[digits + 2] <= '4';
}

void checkReportFolder(const std::filesystem::path& dir) { platform::checkOutputFolder(dir, isReportFile); }

std::vector<std::filesystem::path> writeReport(const MetricResult& r, const std::filesystem::path& dir) {
    // The whole set is made in memory, written into a temporary folder and swapped in: a
    // reader of `dir` sees the previous run's complete set or this one's, never a mix
    // (and a failed run, e.g. a full disk, leaves the previous set untouched).
    std::vector<std::pair<std::string, std::string>> files;
    files.emplace_back("views.csv", viewsCsv(r));
    if (r.pictures) {
        const MetricPictures& p = *r.pictures;
        const std::string stem = "view_" + std::to_string(p.view) + "_";
        files.emplace_back(stem + "i1.png", io::encodePng(p.i1, p.width, p.height, 1, io::PngRows::BottomUp));
        files.emplace_back(stem + "i2.png", io::encodePng(p.i2, p.width, p.height, 1, io::PngRows::BottomUp));
        files.emplace_back(stem + "i3.png", io::encodePng(p.i3, p.width, p.height, 1, io::PngRows::BottomUp));
        files.emplace_back(stem + "i4.png", io::encodePng(p.i4, p.width, p.height, 1, io::PngRows::BottomUp));
    }
    files.emplace_back("summary.json", summaryJson(r));
    platform::writeFolderAtomic(dir, files, isReportFile);
    std::vector<std::filesystem::path> written;
    for (const auto& f : files) written.push_back(dir / f.first);
    return written;
}

}  // namespace metric
