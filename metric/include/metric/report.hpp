// metric/report.hpp: the metric's outputs: views.csv, summary.json, I1..I4 PNGs (paper Fig. 3).
#pragma once
#include <metric/visibility.hpp>
#include <platform/output_folder.hpp>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace metric {

/// CSV, one row per view, columns exactly: view, eye_x, eye_y, eye_z, look_x, look_y,
/// look_z, up_x, up_y, up_z, vfov_deg, width, height, i1, i2, i3, i4, metric, visible,
/// exact. Positions in WORLD metres (origin added back); ratios empty when undefined.
std::string viewsCsv(const MetricResult& result);

/// summary.json: views, views_used, views_excluded (list), metric_mean/min/max,
/// visible_mean, exact_mean (null when absent), seconds, and the options used.
std::string summaryJson(const MetricResult& result);

/// Whether `name` is one of the files writeReport writes (views.csv, summary.json,
/// view_<K>_i<1..4>.png).
bool isReportFile(const std::string& name);
/// Checks before the work that `dir` can take a report: absent, or a folder holding only
/// report files (it is replaced as a whole). Throws core::Error("output: <dir>: ...").
void checkReportFolder(const std::filesystem::path& dir);

/// Writes DIR/views.csv, DIR/summary.json and, if result.pictures is set,
/// DIR/view_<K>_i1.png .. _i4.png as one set: into a temporary folder beside DIR that
/// then replaces DIR atomically (platform::writeFolderAtomic), so DIR never holds a mix of
/// two runs and a failure leaves the previous set whole. Returns the paths written.
/// Throws core::Error("output: ...") as checkReportFolder, or if writing fails.
std::vector<std::filesystem::path> writeReport(const MetricResult& result, const std::filesystem::path& dir);

}  // namespace metric
