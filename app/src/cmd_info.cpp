// app/src/cmd_info.cpp: `ladarvr info FILE|FOLDER... [--json]`: what cloud files hold, as
// pdal info and lasinfo tell it (io::inspectCloud): format, counts, bounds, fields, and
// for LAS, LAZ and COPC the header, the CRS and its units, the classes and returns, the
// extra bytes, the colour depth, the point density and the COPC nodes. Every file is read
// before anything is printed, so a bad one gives its one error line and no output.
#include "cli_common.hpp"
#include "commands.hpp"

#include <core/error.hpp>
#include <io/cloud_info.hpp>
#include <platform/progress.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace app {
namespace {

using Json = nlohmann::ordered_json;  // keys in the order a reader looks for them

struct InfoCli {
    std::vector<std::string> files;
    bool json = false;
};

constexpr int kKeyWidth = 18;              // the text output's keys, padded so the values align
constexpr std::size_t kMostFiles = 65536;  // files of one run, a folder's included

// The points per square unit of the XY bounds, and per square metre when the unit's
// length is known.
struct Density {
    bool known = false;
    double per_unit2 = 0.0;
    std::string unit;  // the horizontal unit's name; empty when the file states none
    bool angular = false;
    double per_m2 = -1.0;  // < 0: not known
};

Density densityOf(const io::CloudInfo& info) {
    Density d;
    const double area = (info.max.x - info.min.x) * (info.max.y - info.min.y);
    if (!info.las || !info.has_bounds || !(area > 0.0) || !std::isfinite(area)) return d;
    const io::CrsUnit& unit = info.las->crs.horizontal_unit;
    d.known = true;
    d.per_unit2 = double(info.points) / area;
    d.unit = unit.name;
    d.angular = unit.angular;
    if (unit.metres > 0.0) d.per_m2 = d.per_unit2 / (unit.metres * unit.metres);
    return d;
}

std::string number(double v, int decimals) {
    char buffer[64];
    std::snprintf(buffer, sizeof buffer, "%.*f", decimals, std::abs(v) < 0.5 * std::pow(10.0, -decimals) ? 0.0 : v);
    return buffer;
}

// 15 significant digits: a header's double as written (0.01, 393775.823060912), no
// trailing zeros.
std::string exact(double v) {
    char buffer[64];
    std::snprintf(buffer, sizeof buffer, "%.15g", v == 0.0 ? 0.0 : v);
    return buffer;
}

// An extra bytes field as the text report gives it: "Deviation (int16; scale 0.1, offset
// 2.5, no data -32768, min -300, max 300)", the values its descriptor states.
std::string extraText(const io::LasExtraField& e) {
    std::string s = e.name + " (" + e.type;
    const std::pair<const char*, const std::optional<double>*> parts[] = {
        {"scale", &e.scale}, {"offset", &e.offset}, {"no data", &e.no_data}, {"min", &e.min}, {"max", &e.max}};
    bool first = true;
    for (const auto& [label, value] : parts) {
        if (!*value) continue;
        s += std::string(first ? "; " : ", ") + label + " " + exact(**value);
        first = false;
    }
    return s + ")";
}

// Three significant digits at least, whatever the magnitude (densities run from 1e-4 up).
std::string figure(double v) {
    char buffer[64];
    std::snprintf(buffer, sizeof buffer, v >= 100.0 ? "%.0f" : "%.3g", v);
    return buffer;
}

// Decimals enough to show the scale's step (0.01 -> 2), 3 without a scale.
int decimalsFor(const io::CloudInfo& info, int axis) {
    if (!info.las) return 3;
    const double s = info.las->scale[axis];
    return std::clamp(int(std::ceil(-std::log10(std::abs(s)) - 1e-9)), 0, 9);
}

const char* colourText(io::ColourDepth c) {
    switch (c) {
        case io::ColourDepth::None: return "none (the point format has no RGB)";
        case io::ColourDepth::Zero: return "all 0 (the RGB fields hold no colour)";
        case io::ColourDepth::EightBit: return "8-bit values in 16-bit fields (every value <= 255)";
        case io::ColourDepth::SixteenBit: return "16-bit";
    }
    return "";
}

const char* colourWord(io::ColourDepth c) {
    switch (c) {
        case io::ColourDepth::None: return "none";
        case io::ColourDepth::Zero: return "zero";
        case io::ColourDepth::EightBit: return "8-bit";
        case io::ColourDepth::SixteenBit: return "16-bit";
    }
    return "";
}

std::string unitText(const io::CrsUnit& u) {
    if (!u.stated()) return "not stated";
    std::string s = core::printable(u.name, 60, true);
    if (u.epsg != 0 && u.name.rfind("EPSG", 0) != 0) s += " (EPSG:" + std::to_string(u.epsg) + ")";
    if (u.epsg == 0 && u.metres > 0.0 && u.metres != 1.0) s += " (" + number(u.metres, 10) + " m)";
    return s;
}

std::string crsText(const io::LasCrs& c) {
    if (c.source.empty()) return c.problem.empty() ? "none (no WKT or GeoTIFF record)" : "none (" + c.problem + ")";
    std::string s = c.name.empty() ? std::string() : "\"" + core::printable(c.name, 120, true) + "\"";
    if (c.epsg != 0) s += (s.empty() ? "" : " ") + std::string("EPSG:") + std::to_string(c.epsg);
    if (s.empty()) s = "unnamed";
    if (!c.kind.empty()) s += ", " + c.kind;
    return s + (c.source == "wkt" ? " (WKT record)" : " (GeoTIFF keys)");
}

// Whether the LAS header's bounds hold every point read (within half a scale step: the
// header's doubles and the points' integers round apart).
bool headerHoldsPoints(const io::CloudInfo& info) {
    const io::LasInfo& las = *info.las;
    for (int k = 0; k < 3; ++k) {
        const double slack = 0.5 * std::abs(las.scale[k]);
        if (las.points_min[k] < info.min[k] - slack || las.points_max[k] > info.max[k] + slack) return false;
    }
    return true;
}

// The heights left out of the survey's span (io::LasInfo::heights), in words.
std::string strayText(const io::CloudInfo& info) {
    const core::HeightSpan::Span& h = info.las->heights;
    if (h.strays_low == 0 && h.strays_high == 0) return "none (no heights far apart from the rest)";
    const int dec = decimalsFor(info, 2);
    std::string s = std::to_string(h.strays_low + h.strays_high) + " apart from the rest by an empty gap:";
    if (h.strays_low) s += " " + std::to_string(h.strays_low) + " below " + number(h.lo, dec) + ",";
    if (h.strays_high) s += " " + std::to_string(h.strays_high) + " above " + number(h.hi, dec) + ",";
    s.back() = ';';
    return s + " z without them " + number(h.lo, dec) + " to " + number(h.hi, dec);
}

void line(const std::string& key, const std::string& value) {
    std::printf("  %-*s %s\n", kKeyWidth, (key + ":").c_str(), value.c_str());
}

void printHistogram(const char* key, const std::map<unsigned, std::uint64_t>& counts, std::uint64_t total,
                    int las_minor, bool classes) {
    const char* what = classes ? (counts.size() == 1 ? " ASPRS class" : " ASPRS classes")
                               : (counts.size() == 1 ? " value" : " values");
    line(key, counts.empty() ? "none" : std::to_string(counts.size()) + what);
    for (const auto& [code, n] : counts) {
        const std::string name = classes ? io::asprsClassName(code, las_minor) : std::string();
        std::printf("    %3u %-26s %12llu %6.1f %%\n", code, name.c_str(), static_cast<unsigned long long>(n),
                    total > 0 ? 100.0 * double(n) / double(total) : 0.0);
    }
}

void printLasPart(const io::CloudInfo& info) {
    const io::LasInfo& las = *info.las;
    const io::LasCrs& crs = las.crs;
    line("CRS", crsText(crs));
    line("horizontal units", unitText(crs.horizontal_unit));
    line("vertical units", unitText(crs.vertical_unit));
    if (!crs.vertical_name.empty() || crs.vertical_epsg != 0) {
        std::string vertical =
            crs.vertical_name.empty() ? "" : "\"" + core::printable(crs.vertical_name, 120, true) + "\"";
        if (crs.vertical_epsg != 0)
            vertical += (vertical.empty() ? "EPSG:" : " EPSG:") + std::to_string(crs.vertical_epsg);
        line("vertical CRS", vertical);
    }
    const Density d = densityOf(info);
    if (!d.known)
        line("density", "not known (the XY bounds have no area)");
    else if (d.per_m2 >= 0.0 && crs.horizontal_unit.metres == 1.0)
        line("density", figure(d.per_unit2) + " points/m² of the XY bounds");
    else if (d.per_m2 >= 0.0)
        line("density", figure(d.per_unit2) + " points per square " + d.unit + " (" + figure(d.per_m2) +
                            " points/m²) of the XY bounds");
    else if (!d.unit.empty())
        line("density", figure(d.per_unit2) + " points per square " + d.unit + " of the XY bounds");
    else
        line("density", figure(d.per_unit2) + " points per square unit of the XY bounds (the file states no units)");
    std::printf("\n");
    line("colour", colourText(las.colour));
    if (las.colour != io::ColourDepth::None)
        line("largest RGB", std::to_string(las.rgb_max[0]) + " " + std::to_string(las.rgb_max[1]) + " " +
                                std::to_string(las.rgb_max[2]));
    std::string extra;
    for (const io::LasExtraField& e : las.extra_fields) extra += (extra.empty() ? "" : ", ") + extraText(e);
    line("extra bytes", extra.empty() ? "none" : extra);
    printHistogram("classes", las.classes, info.points, las.version_minor, true);
    printHistogram("return numbers", las.returns, info.points, las.version_minor, false);
    std::printf("\n");
    line("VLRs", std::to_string(las.records.size()));
    for (const io::LasRecordInfo& r : las.records)
        std::printf("    %-4s %-16s %5u %10llu bytes  %s\n", r.extended ? "EVLR" : "VLR", r.user.c_str(), r.record,
                    static_cast<unsigned long long>(r.bytes), r.description.c_str());
}

void printHuman(const io::CloudInfo& info) {
    std::printf("%s\n", core::printable(info.file.string(), 400, true).c_str());
    std::string format = info.format + (info.version.empty() ? "" : " " + info.version);
    if (!info.encoding.empty()) format += ", " + info.encoding;
    line("format", format);
    line("file size", std::to_string(info.file_bytes) + " bytes");
    if (info.las) {
        const io::LasInfo& las = *info.las;
        line("point format",
             std::to_string(las.point_format) + " (" + std::to_string(las.record_bytes) + "-byte records)");
        line("compressed", las.compressed ? "yes (LAZ)" : "no");
        line("COPC", las.copc ? "yes, " + std::to_string(las.copc_nodes) +
                                    (las.copc_nodes == 1 ? " node with points" : " nodes with points")
                              : "no");
        if (!las.software.empty()) line("software", las.software);
        if (!las.system_id.empty()) line("system", las.system_id);
        if (las.creation_year != 0)
            line("created", "day " + std::to_string(las.creation_day) + " of " + std::to_string(las.creation_year));
    }
    std::printf("\n");
    line("points", std::to_string(info.points));
    if (info.las) {
        std::string counts = "legacy " + std::to_string(info.las->legacy_points);
        if (info.las->points_64) counts += ", LAS 1.4 " + std::to_string(*info.las->points_64);
        line("header counts", counts);
    }
    if (info.non_finite > 0) line("non-finite", std::to_string(info.non_finite) + " points (no bounds counted)");
    std::string fields;
    for (const std::string& f : info.fields) fields += (fields.empty() ? "" : " ") + f;
    line("fields", fields);
    if (!info.has_bounds) line("bounds", "none (no finite point)");
    const char* axes[] = {"x", "y", "z"};
    for (int k = 0; k < 3 && info.has_bounds; ++k) {
        const int dec = decimalsFor(info, k);
        line(std::string("bounds ") + axes[k], number(info.min[k], dec) + " to " + number(info.max[k], dec) +
                                                   " (extent " + number(info.max[k] - info.min[k], dec) + ")");
    }
    if (info.las && info.points > 0 && !headerHoldsPoints(info)) {
        const io::LasInfo& las = *info.las;
        std::string s = "do not hold the points, which lie in";
        for (int k = 0; k < 3; ++k) {
            const int dec = decimalsFor(info, k);
            s += std::string(k ? "," : "") + " " + axes[k] + " " + number(las.points_min[k], dec) + " to " +
                 number(las.points_max[k], dec);
        }
        line("header bounds", s);
    }
    if (info.las && info.points > 0) line("stray returns", strayText(info));
    if (info.las) {
        const io::LasInfo& las = *info.las;
        line("scale", exact(las.scale.x) + " " + exact(las.scale.y) + " " + exact(las.scale.z));
        line("offset", exact(las.offset.x) + " " + exact(las.offset.y) + " " + exact(las.offset.z));
        printLasPart(info);
    }
}

Json vec(const glm::dvec3& v) { return {v.x, v.y, v.z}; }

Json unitJson(const io::CrsUnit& u) {
    if (!u.stated()) return nullptr;
    return {{"name", u.name},
            {"epsg", u.epsg ? Json(u.epsg) : Json(nullptr)},
            {"metres", u.metres > 0.0 ? Json(u.metres) : Json(nullptr)},
            {"angular", u.angular}};
}

Json crsJson(const io::LasCrs& c) {
    const auto orNull = [](const std::string& s) { return s.empty() ? Json(nullptr) : Json(s); };
    const auto codeOrNull = [](int code) { return code ? Json(code) : Json(nullptr); };
    return {{"source", orNull(c.source)},
            {"kind", orNull(c.kind)},
            {"name", orNull(c.name)},
            {"epsg", codeOrNull(c.epsg)},
            {"horizontal_unit", unitJson(c.horizontal_unit)},
            {"vertical_name", orNull(c.vertical_name)},
            {"vertical_epsg", codeOrNull(c.vertical_epsg)},
            {"vertical_unit", unitJson(c.vertical_unit)},
            {"problem", orNull(c.problem)}};
}

Json lasJson(const io::CloudInfo& info) {
    const io::LasInfo& las = *info.las;
    Json j;
    j["point_format"] = las.point_format;
    j["record_bytes"] = las.record_bytes;
    j["compressed"] = las.compressed;
    j["legacy_points"] = las.legacy_points;
    j["points_64"] = las.points_64 ? Json(*las.points_64) : Json(nullptr);
    j["scale"] = vec(las.scale);
    j["offset"] = vec(las.offset);
    j["points_bounds"] = {{"min", vec(las.points_min)}, {"max", vec(las.points_max)}};
    j["header_bounds_hold_points"] = info.points == 0 || headerHoldsPoints(info);
    j["stray_returns"] = {{"below", las.heights.strays_low},
                          {"above", las.heights.strays_high},
                          {"z_without", {las.heights.lo, las.heights.hi}}};
    j["software"] = las.software;
    j["system_id"] = las.system_id;
    j["creation"] = {{"day", las.creation_day}, {"year", las.creation_year}};
    j["crs"] = crsJson(las.crs);
    const Density d = densityOf(info);
    j["density"] = d.known ? Json{{"points_per_unit2", d.per_unit2},
                                  {"unit", d.unit.empty() ? Json(nullptr) : Json(d.unit)},
                                  {"points_per_m2", d.per_m2 >= 0.0 ? Json(d.per_m2) : Json(nullptr)}}
                           : Json(nullptr);
    j["classes"] = Json::array();
    for (const auto& [code, n] : las.classes)
        j["classes"].push_back({{"class", code}, {"name", io::asprsClassName(code, las.version_minor)}, {"points", n}});
    j["returns"] = Json::array();
    for (const auto& [r, n] : las.returns) j["returns"].push_back({{"return_number", r}, {"points", n}});
    j["extra_bytes"] = Json::array();
    const auto maybe = [](const std::optional<double>& v) { return v ? Json(*v) : Json(nullptr); };
    for (const io::LasExtraField& e : las.extra_fields)
        j["extra_bytes"].push_back({{"name", e.name},
                                    {"type", e.type},
                                    {"bytes", e.bytes},
                                    {"description", e.description},
                                    {"scale", maybe(e.scale)},
                                    {"offset", maybe(e.offset)},
                                    {"no_data", maybe(e.no_data)},
                                    {"min", maybe(e.min)},
                                    {"max", maybe(e.max)}});
    j["colour"] = colourWord(las.colour);
    j["rgb_max"] = las.colour == io::ColourDepth::None ? Json(nullptr) : Json(las.rgb_max);
    j["copc"] = las.copc;
    j["copc_nodes"] = las.copc ? Json(las.copc_nodes) : Json(nullptr);
    j["vlrs"] = Json::array();
    for (const io::LasRecordInfo& r : las.records)
        j["vlrs"].push_back({{"user", r.user},
                             {"record", r.record},
                             {"description", r.description},
                             {"bytes", r.bytes},
                             {"extended", r.extended}});
    return j;
}

Json toJson(const io::CloudInfo& info) {
    Json j;
    j["file"] = info.file.string();
    j["bytes"] = info.file_bytes;
    j["format"] = info.format;
    j["version"] = info.version.empty() ? Json(nullptr) : Json(info.version);
    j["encoding"] = info.encoding.empty() ? Json(nullptr) : Json(info.encoding);
    j["points"] = info.points;
    j["non_finite"] = info.non_finite;
    j["bounds"] = info.has_bounds ? Json{{"min", vec(info.min)}, {"max", vec(info.max)}} : Json(nullptr);
    j["fields"] = info.fields;
    j["las"] = info.las ? lasJson(info) : Json(nullptr);
    return j;
}

void run(InfoCli& cli) {
    expandFolderInputs(cli.files, "info", kMostFiles);
    std::vector<io::CloudInfo> infos;
    for (const std::string& file : cli.files) {
        // A bar per file on a terminal (a large survey takes seconds to decode); none otherwise.
        std::unique_ptr<platform::Progress> bar;
        std::uint64_t shown = 0;
        const io::InspectProgress tell = [&](std::uint64_t read, std::uint64_t declared) {
            if (!bar)
                bar = std::make_unique<platform::Progress>(
                    "info: " + core::printable(std::filesystem::path(file).filename().string(), 60), declared);
            bar->advance(std::size_t(read - shown));
            shown = read;
        };
        infos.push_back(io::inspectCloud(file, "info", tell));
        if (bar) bar->finish();
    }
    if (cli.json) {
        Json out = Json::array();
        for (const io::CloudInfo& info : infos) out.push_back(toJson(info));
        // Names and descriptions come from the files: bytes that are not UTF-8 are replaced.
        const std::string text = (infos.size() == 1 ? out[0] : out).dump(2, ' ', false, Json::error_handler_t::replace);
        std::printf("%s\n", text.c_str());
        return;
    }
    for (std::size_t i = 0; i < infos.size(); ++i) {
        if (i > 0) std::printf("\n");
        printHuman(infos[i]);
    }
}

}  // namespace

void registerInfo(CLI::App& cli) {
    auto state = std::make_shared<InfoCli>();
    CLI::App* c = cli.add_subcommand(
        "info",
        "what cloud files hold (PCD, PLY, LAS, LAZ, COPC): format, point count, bounds, fields; for LAS/LAZ the "
        "header, the CRS and its units, the classes and returns, extra bytes, colour depth, density, COPC nodes");
    c->add_option("files", state->files, "the cloud files (a folder gives its .las/.laz files in name order)")
        ->required();
    c->add_flag("--json", state->json, "print one JSON object per file (an array for several) instead");
    c->callback([state] { run(*state); });
}

}  // namespace app
