// io/src/las/las_crs.cpp: the CRS of a LAS file's WKT or GeoTIFF VLRs (io/las_crs.hpp).
// The WKT is parsed into a tree of keyword nodes, bounded in depth and size (the
// record comes from a foreign file); the GeoTIFF key directory is walked with every
// index checked against the arrays it points into (GeoTIFF 1.0 §2.4, §2.7).
#include <io/las_crs.hpp>

#include <core/error.hpp>

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <optional>
#include <string>
#include <vector>

namespace io {
namespace {

// A WKT node: KEYWORD[value, ..., CHILD[...], ...], its quoted and bare values apart from
// its child nodes (the order between the two is not needed here).
struct WktNode {
    std::string keyword;  // upper case
    std::vector<std::string> values;
    std::vector<WktNode> children;
};

constexpr int kWktMaxDepth = 32;
constexpr std::size_t kWktMaxNodes = 20000;

class WktParser {
  public:
    explicit WktParser(std::string_view text) : s_(text) {}

    // The root node; false with problem() set when the text is not WKT.
    bool parse(WktNode& root) {
        skipSpace();
        if (!node(root, 0)) return false;
        skipSpace();
        if (at_ != s_.size()) return fail("text follows the WKT's closing bracket");
        return true;
    }
    const std::string& problem() const { return problem_; }

  private:
    bool fail(const std::string& what) {
        if (problem_.empty()) problem_ = what + " (at byte " + std::to_string(at_) + ")";
        return false;
    }
    void skipSpace() {
        while (at_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[at_]))) ++at_;
    }
    static bool wordChar(char c) {
        return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.' || c == '-' || c == '+';
    }
    std::string word() {
        const std::size_t from = at_;
        while (at_ < s_.size() && wordChar(s_[at_])) ++at_;
        return std::string(s_.substr(from, at_ - from));
    }
    bool quoted(std::string& out) {
        ++at_;  // the opening quote
        for (;;) {
            if (at_ >= s_.size()) return fail("a quoted name is not closed");
            const char c = s_[at_++];
            if (c != '"') {
                out += c;
            } else if (at_ < s_.size() && s_[at_] == '"') {  // "" is a quote inside (WKT 2)
                out += '"';
                ++at_;
            } else {
                return true;
            }
        }
    }
    bool node(WktNode& n, int depth) {
        if (depth >= kWktMaxDepth) return fail("nodes nested deeper than " + std::to_string(kWktMaxDepth));
        if (++nodes_ > kWktMaxNodes) return fail("more than " + std::to_string(kWktMaxNodes) + " nodes");
        n.keyword = word();
        for (char& c : n.keyword) c = char(std::toupper(static_cast<unsigned char>(c)));
        if (n.keyword.empty()) return fail("a keyword is expected");
        skipSpace();
        if (at_ >= s_.size() || (s_[at_] != '[' && s_[at_] != '(')) return fail("'[' is expected after " + n.keyword);
        const char close = s_[at_] == '[' ? ']' : ')';
        ++at_;
        for (;;) {
            skipSpace();
            if (at_ >= s_.size()) return fail(n.keyword + " is not closed");
            if (s_[at_] == '"') {
                std::string v;
                if (!quoted(v)) return false;
                n.values.push_back(std::move(v));
            } else {
                const std::size_t from = at_;
                std::string w = word();
                if (w.empty()) return fail("a value is expected in " + n.keyword);
                skipSpace();
                if (at_ < s_.size() && (s_[at_] == '[' || s_[at_] == '(')) {
                    at_ = from;
                    n.children.emplace_back();
                    if (!node(n.children.back(), depth + 1)) return false;
                } else {
                    n.values.push_back(std::move(w));
                }
            }
            skipSpace();
            if (at_ < s_.size() && s_[at_] == ',') {
                ++at_;
                continue;
            }
            if (at_ < s_.size() && s_[at_] == close) {
                ++at_;
                return true;
            }
            if (at_ >= s_.size()) return fail(n.keyword + " is not closed");
            return fail("',' or '" + std::string(1, close) + "' is expected in " + n.keyword);
        }
    }

    std::string_view s_;
    std::size_t at_ = 0;
    std::size_t nodes_ = 0;
    std::string problem_;
};

bool isOneOf(const std::string& keyword, std::initializer_list<const char*> names) {
    return std::any_of(names.begin(), names.end(), [&](const char* n) { return keyword == n; });
}

const WktNode* childOf(const WktNode& n, std::initializer_list<const char*> names) {
    for (const WktNode& c : n.children)
        if (isOneOf(c.keyword, names)) return &c;
    return nullptr;
}

int parseCode(std::string_view s) {
    int v = 0;
    const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
    return r.ec == std::errc() && r.ptr == s.data() + s.size() && v > 0 ? v : 0;
}

// The EPSG code of AUTHORITY["EPSG","2903"] (WKT 1) or ID["EPSG",2903] (WKT 2); 0 if none.
int epsgOf(const WktNode& n) {
    for (const WktNode& c : n.children) {
        if (!isOneOf(c.keyword, {"AUTHORITY", "ID"}) || c.values.size() < 2) continue;
        std::string authority = c.values[0];
        for (char& ch : authority) ch = char(std::toupper(static_cast<unsigned char>(ch)));
        if (authority == "EPSG") return parseCode(c.values[1]);
    }
    return 0;
}

const char* kindOf(const std::string& keyword) {
    if (isOneOf(keyword, {"PROJCS", "PROJCRS", "PROJECTEDCRS"})) return "projected";
    if (isOneOf(keyword, {"GEOGCS", "GEOGCRS", "GEOGRAPHICCRS", "GEODCRS", "GEODETICCRS"})) return "geographic";
    if (isOneOf(keyword, {"GEOCCS"})) return "geocentric";
    if (isOneOf(keyword, {"COMPD_CS", "COMPOUNDCRS"})) return "compound";
    if (isOneOf(keyword, {"VERT_CS", "VERTCRS", "VERTICALCRS"})) return "vertical";
    return nullptr;
}

// A unit of length named by its length in metres, when it is one of the table's.
struct KnownUnit {
    int epsg;
    const char* name;
    double metres;
    bool angular;
};
constexpr std::array<KnownUnit, 10> kUnits = {{
    {9001, "metre", 1.0, false},
    {9002, "foot", 0.3048, false},
    {9003, "US survey foot", 1200.0 / 3937.0, false},
    {9005, "Clarke's foot", 0.3047972654, false},
    {9030, "nautical mile", 1852.0, false},
    {9036, "kilometre", 1000.0, false},
    {9093, "statute mile", 1609.344, false},
    {9101, "radian", 0.0, true},
    {9102, "degree", 0.0, true},
    {9122, "degree", 0.0, true},
}};

// The unit of a UNIT / LENGTHUNIT / ANGLEUNIT node: the table's name where its code or
// (for a length) its factor is the table's, else the file's name and factor.
CrsUnit unitOf(const WktNode& u, bool angular) {
    CrsUnit unit;
    unit.name = u.values.empty() ? std::string("unnamed") : u.values[0];
    unit.epsg = epsgOf(u);
    unit.angular = angular || u.keyword == "ANGLEUNIT";
    double factor = 0.0;
    if (u.values.size() >= 2) {
        const std::string& f = u.values[1];
        const auto r = std::from_chars(f.data(), f.data() + f.size(), factor);
        if (r.ec != std::errc() || !std::isfinite(factor) || factor <= 0.0) factor = 0.0;
    }
    if (!unit.angular) unit.metres = factor;
    for (const KnownUnit& k : kUnits) {
        const bool same_factor =
            !unit.angular && !k.angular && factor > 0.0 && std::fabs(factor - k.metres) <= 1e-12 * k.metres;
        if ((unit.epsg != 0 && unit.epsg == k.epsg) || (unit.epsg == 0 && same_factor)) {
            unit.name = k.name;
            unit.epsg = k.epsg;
            unit.angular = k.angular;
            unit.metres = k.angular ? 0.0 : k.metres;  // a code naming an angle: no length, whatever the factor
            break;
        }
    }
    return unit;
}

// The unit of a CRS node's coordinates: its own UNIT / LENGTHUNIT / ANGLEUNIT (WKT 1,
// and WKT 2 where one unit serves every axis), else its first axis's (WKT 2).
CrsUnit crsUnit(const WktNode& crs) {
    const bool geographic = kindOf(crs.keyword) == std::string_view("geographic");
    if (const WktNode* u = childOf(crs, {"UNIT", "LENGTHUNIT", "ANGLEUNIT"})) return unitOf(*u, geographic);
    for (const WktNode& axis : crs.children)
        if (axis.keyword == "AXIS")
            if (const WktNode* u = childOf(axis, {"UNIT", "LENGTHUNIT", "ANGLEUNIT"})) return unitOf(*u, geographic);
    return {};
}

}  // namespace

CrsUnit epsgUnit(int code) {
    for (const KnownUnit& k : kUnits)
        if (k.epsg == code) return {k.name, k.epsg, k.metres, k.angular};
    return {"EPSG unit " + std::to_string(code), code, 0.0, false};
}

LasCrs crsFromWkt(std::string_view wkt) {
    LasCrs crs;
    wkt = wkt.substr(0, std::min(wkt.size(), wkt.find('\0')));
    const std::size_t first = wkt.find_first_not_of(" \t\r\n");
    if (first == std::string_view::npos || wkt.find('[') == std::string_view::npos) {
        crs.problem = first == std::string_view::npos
                          ? "the WKT record is empty"
                          : "the WKT record holds no CRS (its text: " + core::printable(wkt.substr(first), 60) + ")";
        return crs;
    }
    WktNode root;
    WktParser parser(wkt.substr(first));
    if (!parser.parse(root)) {
        crs.problem = "the WKT record cannot be read: " + parser.problem();
        return crs;
    }
    const char* kind = kindOf(root.keyword);
    if (!kind) {
        crs.problem = "the WKT record's " + core::printable(root.keyword, 40) + " is not a CRS";
        return crs;
    }
    crs.source = "wkt";
    crs.kind = kind;
    crs.name = root.values.empty() ? std::string() : root.values[0];
    crs.epsg = epsgOf(root);
    const WktNode* horizontal = &root;
    const WktNode* vertical = crs.kind == "vertical" ? &root : nullptr;
    if (crs.kind == "compound") {
        horizontal = nullptr;
        for (const WktNode& c : root.children) {
            const char* k = kindOf(c.keyword);
            if (!k) continue;
            if (std::string_view(k) == "vertical")
                vertical = vertical ? vertical : &c;
            else
                horizontal = horizontal ? horizontal : &c;
        }
        if (crs.epsg == 0 && horizontal) crs.epsg = epsgOf(*horizontal);
    }
    if (horizontal && horizontal != vertical) crs.horizontal_unit = crsUnit(*horizontal);
    if (vertical) {
        crs.vertical_name = vertical->values.empty() ? std::string() : vertical->values[0];
        crs.vertical_epsg = epsgOf(*vertical);
        crs.vertical_unit = crsUnit(*vertical);
    }
    return crs;
}

namespace {

// GeoTIFF keys (GeoTIFF 1.0 §6.2) and codes.
enum GeoKey : std::uint16_t {
    kModelType = 1024,
    kCitation = 1026,
    kGeographicType = 2048,
    kGeogCitation = 2049,
    kGeogAngularUnits = 2054,
    kProjectedCsType = 3072,
    kPcsCitation = 3073,
    kProjLinearUnits = 3076,
    kProjLinearUnitSize = 3077,
    kVerticalCsType = 4096,
    kVerticalCitation = 4097,
    kVerticalUnits = 4099,
};
constexpr std::uint16_t kDoublesTag = 34736, kAsciiTag = 34737;
constexpr int kUserDefined = 32767;

// The directory's keys, each a short, a double or a text, indices checked.
struct GeoKeys {
    std::vector<std::pair<std::uint16_t, int>> shorts;
    std::vector<std::pair<std::uint16_t, double>> doubles;
    std::vector<std::pair<std::uint16_t, std::string>> texts;

    int shortOf(std::uint16_t key) const {
        for (const auto& [k, v] : shorts)
            if (k == key) return v;
        return 0;
    }
    // A code that names something (not 0 undefined, not 32767 user-defined).
    int codeOf(std::uint16_t key) const {
        const int v = shortOf(key);
        return v > 0 && v < kUserDefined ? v : 0;
    }
    std::optional<double> doubleOf(std::uint16_t key) const {
        for (const auto& [k, v] : doubles)
            if (k == key) return v;
        return std::nullopt;
    }
    std::string textOf(std::uint16_t key) const {
        for (const auto& [k, v] : texts)
            if (k == key) return v;
        return {};
    }
};

std::uint16_t u16(std::string_view b, std::size_t i) {
    std::uint16_t v;
    std::memcpy(&v, b.data() + 2 * i, 2);
    return v;
}

// Reads the directory; returns the problem, or empty.
std::string readGeoKeys(std::string_view directory, std::string_view doubles, std::string_view ascii, GeoKeys& out) {
    const std::size_t shorts = directory.size() / 2;
    if (shorts < 4)
        return "the GeoTIFF key directory has " + std::to_string(directory.size()) + " bytes; at least 8 needed";
    const std::size_t keys = u16(directory, 3);
    if (u16(directory, 0) != 1)
        return "the GeoTIFF key directory's version is " + std::to_string(u16(directory, 0)) + "; allowed: 1";
    if (4 + 4 * keys > shorts)
        return "the GeoTIFF key directory lists " + std::to_string(keys) + " keys but holds room for " +
               std::to_string((shorts - 4) / 4);
    for (std::size_t i = 0; i < keys; ++i) {
        const std::uint16_t id = u16(directory, 4 + 4 * i), where = u16(directory, 5 + 4 * i);
        const std::size_t count = u16(directory, 6 + 4 * i), value = u16(directory, 7 + 4 * i);
        if (where == 0) {
            out.shorts.emplace_back(id, int(value));
        } else if (where == kDoublesTag) {
            if (count < 1 || value >= doubles.size() / 8) continue;  // outside the doubles: not used
            double d;
            std::memcpy(&d, doubles.data() + 8 * value, 8);
            if (std::isfinite(d)) out.doubles.emplace_back(id, d);
        } else if (where == kAsciiTag) {
            if (value >= ascii.size()) continue;
            // A count past the end (writers that count a NUL the record lacks): what is there.
            std::string text(ascii.substr(value, std::min(count, ascii.size() - value)));
            text = text.substr(0, std::min(text.size(), text.find('\0')));
            while (!text.empty() && (text.back() == '|' || text.back() == ' ')) text.pop_back();
            out.texts.emplace_back(id, std::move(text));
        }
    }
    return {};
}

// A citation that names something ("unknown" names nothing).
std::string citation(const std::string& s) {
    std::string lower = s;
    for (char& c : lower) c = char(std::tolower(static_cast<unsigned char>(c)));
    return lower == "unknown" || lower == "undefined" ? std::string() : s;
}

// The unit a linear-units key and its size key give.
CrsUnit linearUnit(const GeoKeys& keys, std::uint16_t units_key, std::optional<std::uint16_t> size_key) {
    const int code = keys.shortOf(units_key);
    if (code > 0 && code < kUserDefined) return epsgUnit(code);
    if (code == kUserDefined && size_key)
        if (const std::optional<double> m = keys.doubleOf(*size_key); m && *m > 0.0)
            return {"user-defined", 0, *m, false};
    return {};
}

}  // namespace

LasCrs crsFromGeoKeys(std::string_view directory, std::string_view doubles, std::string_view ascii) {
    LasCrs crs;
    GeoKeys keys;
    if (std::string problem = readGeoKeys(directory, doubles, ascii, keys); !problem.empty()) {
        crs.problem = problem;
        return crs;
    }
    const int model = keys.shortOf(kModelType);
    const int projected = keys.codeOf(kProjectedCsType), geographic = keys.codeOf(kGeographicType);
    const bool is_projected = model == 1 || (model == 0 && keys.shortOf(kProjectedCsType) != 0);
    crs.kind = is_projected                    ? "projected"
               : model == 2 || geographic != 0 ? "geographic"
               : model == 3                    ? "geocentric"
                                               : "";
    crs.epsg = is_projected ? projected : geographic;
    crs.name = citation(keys.textOf(is_projected ? kPcsCitation : kGeogCitation));
    if (crs.name.empty()) crs.name = citation(keys.textOf(kCitation));
    if (is_projected) {
        crs.horizontal_unit = linearUnit(keys, kProjLinearUnits, kProjLinearUnitSize);
    } else if (!crs.kind.empty()) {
        const int angular = keys.codeOf(kGeogAngularUnits);
        crs.horizontal_unit = epsgUnit(angular != 0 ? angular : 9102);  // GeoTIFF's default: degree
    }
    crs.vertical_epsg = keys.codeOf(kVerticalCsType);
    crs.vertical_name = citation(keys.textOf(kVerticalCitation));
    crs.vertical_unit = linearUnit(keys, kVerticalUnits, std::nullopt);
    if (crs.kind.empty() && crs.epsg == 0 && !crs.vertical_unit.stated() && crs.vertical_epsg == 0) {
        crs.problem = "the GeoTIFF keys name no CRS (no model type, projected or geographic CRS)";
        return crs;
    }
    crs.source = "geotiff";
    return crs;
}

}  // namespace io
