// corpus: SPEC.json parsing. Everything is checked here, before any item is built, so a
// typo costs one line and no work; sim::validate sees the extreme corners of the ranges.
#include <corpus/spec.hpp>

#include <core/error.hpp>
#include <io/strict_json.hpp>
#include <platform/safe_file.hpp>
#include <platform/sha256.hpp>
#include <sim/generator.hpp>
#include <sim/sensor.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace corpus {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

constexpr double kBig = 1e300;
constexpr double kIntLimit = 2147483647.0;
// What a vary key sets; the integer keys' values are whole already (VaryKey::integer).
using Options = sim::GenerateOptions;

}  // namespace

const std::vector<VaryKey> kVaryKeys = {
    {"target_yaw_deg", false, -3600, 3600, "the target's yaw about world z, degrees (replaces the scene's)"},
    {"target_offset_m", false, 0, 1e6, "distance the target moves from its place, uniform over the disc (annulus)"},
    {"environment_keep_fraction", false, 0, 1, "fraction of environment meshes kept (the others are left out)"},
    {"centre_offset_m", false, 0, 1e6, "distance the orbit centre C moves away from the target, uniform over the disc"},
    {"altitude_m", false, -kBig, kBig, "drone altitude above C (generate --altitude-m)", "--altitude-m",
     [](Options& o, double v) { o.orbit.altitude_m = v; }},
    {"overlap_m", false, -kBig, kBig, "CO (generate --overlap-m)", "--overlap-m",
     [](Options& o, double v) { o.orbit.overlap_m = v; }},
    {"alpha_deg", false, -kBig, kBig, "sensor inclination (generate --alpha-deg)", "--alpha-deg",
     [](Options& o, double v) { o.orbit.inclination_deg = v; }},
    {"fov_deg", false, -kBig, kBig, "field of view (generate --fov-deg)", "--fov-deg",
     [](Options& o, double v) { o.orbit.fov_deg = v; }},
    {"resolution", true, 1, 65536, "pixels across and down (generate --xres and --yres together)", "--xres --yres",
     [](Options& o, double v) { o.orbit.xres = o.orbit.yres = int(v); }},
    {"xres", true, 1, 65536, "pixels across (generate --xres)", "--xres",
     [](Options& o, double v) { o.orbit.xres = int(v); }},
    {"yres", true, 1, 65536, "pixels down (generate --yres)", "--yres",
     [](Options& o, double v) { o.orbit.yres = int(v); }},
    {"views", true, 1, 65535, "NoV (generate --views)", "--views",
     [](Options& o, double v) { o.orbit.views = int(v); }},
    {"band_m", false, -kBig, kBig, "RANSAC band (generate --band-m)", "--band-m",
     [](Options& o, double v) { o.ground.ransac.band_m = v; }},
    {"ransac_distance_m", false, -kBig, kBig, "RANSAC inlier distance (generate --ransac-distance-m)",
     "--ransac-distance-m", [](Options& o, double v) { o.ground.ransac.distance_threshold_m = v; }},
    {"min_normal_z", false, -kBig, kBig, "generate --min-normal-z", "--min-normal-z",
     [](Options& o, double v) { o.ground.ransac.min_normal_z = v; }},
    {"stop_fraction", false, -kBig, kBig, "generate --stop-fraction", "--stop-fraction",
     [](Options& o, double v) { o.ground.ransac.stop_fraction = v; }},
    {"min_plane_fraction", false, -kBig, kBig, "generate --min-plane-fraction", "--min-plane-fraction",
     [](Options& o, double v) { o.ground.ransac.min_plane_fraction = v; }},
    {"max_planes", true, -kIntLimit, kIntLimit, "generate --max-planes", "--max-planes",
     [](Options& o, double v) { o.ground.ransac.max_planes = int(v); }},
    {"ransac_iterations", true, -kIntLimit, kIntLimit, "generate --ransac-iterations", "--ransac-iterations",
     [](Options& o, double v) { o.ground.ransac.ransac_iterations = int(v); }},
    {"ransac_sample_points", true, -kIntLimit, kIntLimit, "generate --ransac-sample-points", "--ransac-sample-points",
     [](Options& o, double v) { o.ground.ransac.ransac_sample_points = int(v); }},
    {"colours", true, -kIntLimit, kIntLimit, "entries of the jet map (generate --colours)", "--colours",
     [](Options& o, double v) { o.colour.entries = int(v); }},
    {"ransac_seed", true, 0, 9007199254740992.0, "RANSAC seed (generate --seed)", "--seed",
     [](Options& o, double v) { o.seed = std::uint64_t(v); }},
    {"sensor_preset", true, 0, double(sim::sensorPresetCount() - 1),
     "the sensor model: a preset's name (generate --sensor), or its place in the list of presets, from 0 (ideal)",
     "--sensor", [](Options& o, double v) { o.sensor = sim::sensorPreset(sim::sensorPresetNames()[std::size_t(v)]); },
     sim::sensorPresetNames},
};

const VaryKey* findVaryKey(std::string_view name) {
    const auto k = std::find_if(kVaryKeys.begin(), kVaryKeys.end(), [&](const VaryKey& vk) { return vk.name == name; });
    return k == kVaryKeys.end() ? nullptr : &*k;
}

void applyToOptions(sim::GenerateOptions& o, std::string_view key, double value) {
    const VaryKey* k = findVaryKey(key);
    if (k && k->apply) k->apply(o, value);
}

double NumberVary::lowest() const {
    return kind == Kind::Choice ? *std::min_element(choices.begin(), choices.end()) : min;
}
double NumberVary::highest() const {
    return kind == Kind::Choice ? *std::max_element(choices.begin(), choices.end()) : max;
}

bool Spec::varies(std::string_view key) const {
    if (key == "target_files") return !target_files.empty();
    return numbers.count(std::string(key)) > 0;
}

std::string Spec::cloudName() const {
    switch (format) {
        case io::CloudFormat::PlyBinary:
        case io::CloudFormat::PlyAscii: return "cloud.ply";
        case io::CloudFormat::Las: return "cloud.las";
        case io::CloudFormat::Laz: return "cloud.laz";
        case io::CloudFormat::Copc: return "cloud.copc.laz";
        default: return "cloud.pcd";
    }
}

namespace {

struct Context {
    std::string prefix;  // "corpus: <spec>: "
    [[noreturn]] void fail(const std::string& key, const std::string& what) const {
        throw core::Error(prefix + key + ": " + what);
    }
};

std::string keyList() {
    std::string s;
    for (const VaryKey& k : kVaryKeys) s += std::string(k.name) + ", ";
    return s + "target_files";
}

std::string rangeText(const VaryKey& k) {
    if (k.lowest <= -kBig && k.highest >= kBig) return "finite numbers";
    return std::string(k.integer ? "integers" : "numbers") + " in [" + core::shownNumber(k.lowest) + ", " +
           core::shownNumber(k.highest) + "]";
}

double numberValue(const Context& c, const std::string& key, const json& v, const VaryKey& k) {
    if (k.names && v.is_string()) {
        const auto names = k.names();
        for (std::size_t i = 0; i < names.size(); ++i)
            if (names[i] == v.get<std::string>()) return double(i);
        std::string list;
        for (const std::string_view n : names) list += (list.empty() ? "" : ", ") + std::string(n);
        c.fail(key, "'" + core::printable(v.get<std::string>(), 40) + "' is not a name; allowed " + list +
                        " or their places in that list, " + rangeText(k));
    }
    if (!v.is_number() || (v.is_number_float() && !std::isfinite(v.get<double>())))
        c.fail(key, "'" + v.dump() + "' is not a number; allowed " + rangeText(k));
    const double d = v.get<double>();
    if (k.integer && (v.is_number_float() && d != std::floor(d)))
        c.fail(key, core::shownNumber(d) + " is not an integer; allowed " + rangeText(k));
    if (d < k.lowest || d > k.highest) c.fail(key, core::shownNumber(d) + " is out of range; allowed " + rangeText(k));
    return d;
}

NumberVary parseNumber(const Context& c, const std::string& key, const json& v, const VaryKey& k) {
    NumberVary n;
    n.integer = k.integer;
    const std::string allowed =
        "allowed a number, {\"min\": a, \"max\": b} with a <= b, or a non-empty list of " + rangeText(k);
    if (v.is_object()) {
        for (auto it = v.begin(); it != v.end(); ++it)
            if (it.key() != "min" && it.key() != "max")
                c.fail(key, "unknown key '" + core::printable(it.key(), 40) + "' in the range; allowed min, max");
        if (!v.contains("min") || !v.contains("max"))
            c.fail(key,
                   std::string("empty range: '") + (v.contains("min") ? "max" : "min") + "' is missing; " + allowed);
        n.kind = NumberVary::Kind::Uniform;
        n.min = numberValue(c, key + ".min", v["min"], k);
        n.max = numberValue(c, key + ".max", v["max"], k);
        if (n.min > n.max)
            c.fail(key, "min " + core::shownNumber(n.min) + " > max " + core::shownNumber(n.max) + "; " + allowed);
    } else if (v.is_array()) {
        if (v.empty()) c.fail(key, "empty list; " + allowed);
        n.kind = NumberVary::Kind::Choice;
        for (std::size_t i = 0; i < v.size(); ++i)
            n.choices.push_back(numberValue(c, key + "[" + std::to_string(i) + "]", v[i], k));
    } else if (v.is_number() || (k.names && v.is_string())) {
        n.kind = NumberVary::Kind::Fixed;
        n.min = n.max = numberValue(c, key, v, k);
    } else {
        c.fail(key, "'" + core::printable(v.dump(), 60) + "' is not a range; " + allowed);
    }
    return n;
}

TargetModel parseTarget(const Context& c, const std::string& key, const json& v, const fs::path& dir) {
    TargetModel t;
    const std::string allowed = "allowed a file name or {\"file\": name, \"up\": \"y\"|\"z\", \"scale\": s > 0}";
    json file;
    if (v.is_string()) {
        file = v;
    } else if (v.is_object()) {
        for (auto it = v.begin(); it != v.end(); ++it) {
            if (it.key() == "file") {
                file = it.value();
            } else if (it.key() == "up") {
                if (!it.value().is_string() || (it.value() != "y" && it.value() != "z"))
                    c.fail(key + ".up", "'" + core::printable(it.value().dump(), 40) + "'; allowed y, z");
                t.up = it.value().get<std::string>();
            } else if (it.key() == "scale") {
                if (!it.value().is_number() || !(it.value().get<double>() > 0) ||
                    !std::isfinite(it.value().get<double>()))
                    c.fail(key + ".scale", "'" + core::printable(it.value().dump(), 40) + "'; allowed a number > 0");
                t.scale = it.value().get<double>();
            } else {
                c.fail(key, "unknown key '" + core::printable(it.key(), 40) + "'; allowed file, up, scale");
            }
        }
    }
    if (!file.is_string() || file.get<std::string>().empty()) c.fail(key, allowed);
    t.written = file.get<std::string>();
    t.file = fs::absolute(dir / t.written).lexically_normal();
    const std::string problem = platform::regularFileProblem(t.file);
    if (!problem.empty()) c.fail(key, "'" + core::printable(t.written) + "' " + problem + "; allowed: a mesh file");
    return t;
}

}  // namespace

Spec parseSpec(std::string_view text, const fs::path& file) {
    Spec s;
    s.file = fs::absolute(file).lexically_normal();
    const Context c{"corpus: " + core::printable(file.string()) + ": "};
    // Strict: a key given twice or a NUL in a string is refused, naming where it is.
    const json j = io::parseStrictJson(text, "corpus: " + core::printable(file.string()));
    if (!j.is_object())
        throw core::Error(c.prefix + "allowed a JSON object with scene, count, seed, vary, metric, format");
    const fs::path dir = s.file.parent_path();
    for (auto it = j.begin(); it != j.end(); ++it) {
        const std::string& key = it.key();
        const json& v = it.value();
        if (key == "scene") {
            if (!v.is_string() || v.get<std::string>().empty()) c.fail(key, "allowed a scene file name");
            s.scene = fs::absolute(dir / v.get<std::string>()).lexically_normal();
            const std::string problem = platform::regularFileProblem(s.scene);
            if (!problem.empty())
                c.fail(key, "'" + core::printable(v.get<std::string>()) + "' " + problem + "; allowed: a scene file");
        } else if (key == "count") {
            if (!v.is_number_integer() || v.get<double>() < 1 || v.get<double>() > double(kMaxItems))
                c.fail(key, "'" + core::printable(v.dump(), 40) + "'; allowed an integer in [1, " +
                                std::to_string(kMaxItems) + "]");
            s.count = v.get<std::size_t>();
        } else if (key == "seed") {
            if (!v.is_number_unsigned())
                c.fail(key, "'" + core::printable(v.dump(), 40) + "'; allowed an integer in [0, 2^64)");
            s.seed = v.get<std::uint64_t>();
        } else if (key == "metric") {
            if (v.is_boolean()) {
                s.metric.enabled = v.get<bool>();
            } else if (v.is_object()) {
                s.metric.enabled = true;
                for (auto m = v.begin(); m != v.end(); ++m) {
                    int* field = m.key() == "views"    ? &s.metric.views
                                 : m.key() == "width"  ? &s.metric.width
                                 : m.key() == "height" ? &s.metric.height
                                                       : nullptr;
                    if (!field)
                        c.fail("metric",
                               "unknown key '" + core::printable(m.key(), 40) + "'; allowed views, width, height");
                    const bool is_views = m.key() == "views";
                    const double lo = is_views ? 1 : 16, hi = is_views ? 65535 : 8192;
                    if (!m.value().is_number_integer() || m.value().get<double>() < lo || m.value().get<double>() > hi)
                        c.fail("metric." + m.key(), "'" + core::printable(m.value().dump(), 40) +
                                                        "'; allowed an integer in [" + core::shownNumber(lo) + ", " +
                                                        core::shownNumber(hi) + "]");
                    *field = m.value().get<int>();
                }
            } else {
                c.fail(key, "allowed true, false or {\"views\": n, \"width\": w, \"height\": h}");
            }
        } else if (key == "format") {
            if (!v.is_string()) c.fail(key, "allowed pcd, pcd-ascii, ply, ply-ascii");
            s.format = io::parseCloudFormat(v.get<std::string>(), c.prefix + "format");
        } else if (key == "vary") {
            if (!v.is_object()) c.fail(key, "allowed an object whose keys are " + keyList());
            for (auto m = v.begin(); m != v.end(); ++m) {
                const std::string name = "vary." + m.key();
                if (m.key() == "target_files") {
                    const json& list = m.value();
                    if (list.is_array()) {
                        if (list.empty()) c.fail(name, "empty list; allowed a non-empty list of mesh files");
                        for (std::size_t i = 0; i < list.size(); ++i)
                            s.target_files.push_back(
                                parseTarget(c, name + "[" + std::to_string(i) + "]", list[i], dir));
                    } else {
                        s.target_files.push_back(parseTarget(c, name, list, dir));
                    }
                    continue;
                }
                const VaryKey* k = findVaryKey(m.key());
                if (!k) c.fail(name, "unknown key; allowed " + keyList());
                s.numbers[m.key()] = parseNumber(c, name, m.value(), *k);
            }
        } else if (key == "placement") {
            if (!v.is_string() || (v.get<std::string>() != "boxes" && v.get<std::string>() != "triangles"))
                c.fail(key, "'" + core::printable(v.dump(), 40) + "'; allowed \"boxes\" or \"triangles\"");
            s.place_by_triangles = v.get<std::string>() == "triangles";
        } else if (key == "comment") {
            if (!v.is_string()) c.fail(key, "allowed a string");
        } else {
            c.fail(key, "unknown key; allowed scene, count, seed, vary, metric, format, placement, comment");
        }
    }
    if (s.scene.empty()) c.fail("scene", "missing; allowed a scene file name (relative to the SPEC)");
    if (s.count == 0) c.fail("count", "missing; allowed an integer in [1, " + std::to_string(kMaxItems) + "]");
    if (s.numbers.count("resolution") && (s.numbers.count("xres") || s.numbers.count("yres")))
        c.fail("vary.resolution", "given with xres/yres; allowed one of resolution or xres/yres");
    // The generator's own limits, at both extreme corners of the ranges (alpha + fov/2,
    // the drone radius and the memory plan grow with the values).
    for (const bool high : {false, true}) {
        sim::GenerateOptions o;
        for (const auto& [key, n] : s.numbers) applyToOptions(o, key, high ? n.highest() : n.lowest());
        try {
            sim::validate(o);
        } catch (const core::Error& e) {
            throw core::Error(c.prefix + "vary: with every value at its " + (high ? "highest" : "lowest") + ": " +
                              e.what());
        }
    }
    s.sha256 = platform::sha256Hex(text);
    return s;
}

Spec loadSpec(const fs::path& file) {
    const std::string text =
        platform::readTextFile(file, kMaxSpecBytes, "corpus: SPEC " + core::printable(file.string()));
    Spec s = parseSpec(text, file);
    return s;
}

}  // namespace corpus
