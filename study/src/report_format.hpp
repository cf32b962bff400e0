// study/src/report_format.hpp: how the study report writes its numbers (CSV, JSON and the
// HTML page alike): a figure within 1e-12 of 0 is what rounding left of a zero (a standard
// deviation of 7.1e-15 over equal values) and is written as 0; p values are written as
// computed, since an exact p can be that small. Also the JSON tables (report_json.cpp).
#pragma once
#include <study/report.hpp>

#include <cmath>
#include <cstdio>
#include <string>

namespace study::detail {

/// Below this magnitude a figure is written as 0.
inline constexpr double kZeroBelow = 1e-12;

/// `v` as the report shows it: 0 (never -0) within kZeroBelow of 0, else `v`.
inline double shownValue(double v) { return std::fabs(v) < kZeroBelow ? 0.0 : v; }

/// A figure for a CSV cell: nine significant digits, "" for NaN (does not apply).
inline std::string csvNumber(double v) {
    if (std::isnan(v)) return "";
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.9g", shownValue(v));
    return buf;
}

/// A p value for a CSV cell: as csvNumber, without rounding small values to 0.
inline std::string csvP(double p) {
    if (std::isnan(p)) return "";
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.9g", p);
    return buf;
}

/// figures.json: every figure of the report in one document.
std::string figuresJson(const StudyResults& results, const ReportFigures& figures);

}  // namespace study::detail
