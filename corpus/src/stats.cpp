// corpus: statistics over a manifest, the histogram picture, and study plans.
#include <corpus/random.hpp>
#include <corpus/run.hpp>
#include <corpus/stats.hpp>

#include <core/error.hpp>
#include <io/png.hpp>
#include <platform/atomic_file.hpp>
#include <platform/safe_file.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>

namespace corpus {

namespace fs = std::filesystem;
using nlohmann::json;

std::vector<std::pair<std::string, double>> manifestColumns(const std::string& line) {
    std::vector<std::pair<std::string, double>> out;
    const json j = json::parse(line);
    for (auto it = j.begin(); it != j.end(); ++it)
        if (it.value().is_number() && it.key() != "seed" && it.key() != "item_seed" && it.key() != "index")
            out.emplace_back(it.key(), it.value().get<double>());
    if (j.contains("values"))
        for (auto it = j["values"].begin(); it != j["values"].end(); ++it)
            if (it.value().is_number()) out.emplace_back(it.key(), it.value().get<double>());
    if (j.contains("points_per_label"))
        for (auto it = j["points_per_label"].begin(); it != j["points_per_label"].end(); ++it)
            if (it.value().is_number()) out.emplace_back("points_" + it.key(), it.value().get<double>());
    return out;
}

namespace {

double quantile(const std::vector<double>& sorted, double q) {
    const std::size_t k = std::size_t(std::ceil(q * double(sorted.size())));
    return sorted[std::min(sorted.size() - 1, k == 0 ? 0 : k - 1)];
}

std::map<std::string, std::vector<double>> columnsOf(const std::vector<std::string>& lines) {
    std::map<std::string, std::vector<double>> columns;
    for (const std::string& line : lines)
        for (const auto& [name, v] : manifestColumns(line)) columns[name].push_back(v);
    return columns;
}

std::string columnList(const std::map<std::string, std::vector<double>>& columns) {
    std::string s;
    for (const auto& [name, v] : columns) s += (s.empty() ? "" : ", ") + core::printable(name, 40);
    return s.empty() ? "none (the manifest's lines hold no numeric column)" : s;
}

/// Bars of item counts, white background, dark grey bars, one pixel gap between bins.
void writeHistogram(const fs::path& path, const std::vector<std::size_t>& bins) {
    const int width = 480, height = 240, margin = 10;
    std::vector<std::uint8_t> rgb(std::size_t(width) * height * 3, 255);
    const std::size_t top = std::max<std::size_t>(1, *std::max_element(bins.begin(), bins.end()));
    const int bin_w = (width - 2 * margin) / int(bins.size());
    for (std::size_t b = 0; b < bins.size(); ++b) {
        const int bar_h = int(std::lround(double(bins[b]) / double(top) * (height - 2 * margin)));
        for (int y = height - margin - bar_h; y < height - margin; ++y)
            for (int x = margin + int(b) * bin_w; x < margin + int(b + 1) * bin_w - 1; ++x)
                for (int c = 0; c < 3; ++c) rgb[(std::size_t(y) * width + x) * 3 + c] = c == 2 ? 160 : 60;
    }
    for (int x = margin; x < width - margin; ++x)  // the axis
        for (int c = 0; c < 3; ++c) rgb[(std::size_t(height - margin) * width + x) * 3 + c] = 0;
    io::writePng(path, rgb, width, height, 3);
}

}  // namespace

Stats computeStats(const fs::path& dir, const StatsOptions& o) {
    platform::InputSet inputs;
    const std::vector<std::string> lines = readManifest(dir, inputs);
    platform::checkWritableDestination(o.histogram, inputs);  // before any work: not one of the inputs
    auto columns = columnsOf(lines);
    Stats st;
    st.items = lines.size();
    for (auto& [name, v] : columns) {
        std::sort(v.begin(), v.end());
        ColumnStats c;
        c.name = name;
        c.n = v.size();
        c.min = v.front();
        c.max = v.back();
        c.p10 = quantile(v, 0.1);
        c.median = quantile(v, 0.5);
        c.p90 = quantile(v, 0.9);
        double sum = 0;
        for (double x : v) sum += x;
        c.mean = sum / double(v.size());
        st.columns.push_back(c);
    }
    st.histogram_column = !o.column.empty() ? o.column : columns.count("metric") ? "metric" : "points";
    const auto it = columns.find(st.histogram_column);
    if (it == columns.end())
        throw core::Error("corpus: --column '" + core::printable(st.histogram_column, 40) + "' is not in " +
                          core::printable(dir.string()) + "'s manifest; allowed " + columnList(columns));
    if (o.bins < 1 || o.bins > 200) throw core::Error("corpus: bins: allowed [1, 200]");
    const std::vector<double>& v = it->second;
    st.histogram_lo = v.front();
    st.histogram_hi = v.back();
    st.histogram.assign(std::size_t(o.bins), 0);
    const double span = st.histogram_hi - st.histogram_lo;
    for (double x : v) {
        std::size_t b = span > 0 ? std::size_t((x - st.histogram_lo) / span * o.bins) : 0;
        ++st.histogram[std::min(b, st.histogram.size() - 1)];
    }
    st.histogram_png = o.histogram;
    writeHistogram(o.histogram, st.histogram);
    return st;
}

std::string statsText(const Stats& st) {
    std::string s = "corpus: " + std::to_string(st.items) + " items\n";
    char line[256];
    std::snprintf(line, sizeof line, "%-26s %6s %12s %12s %12s %12s %12s %12s\n", "column", "n", "min", "p10", "median",
                  "p90", "max", "mean");
    s += line;
    for (const ColumnStats& c : st.columns) {
        std::snprintf(line, sizeof line, "%-26s %6zu %12.6g %12.6g %12.6g %12.6g %12.6g %12.6g\n", c.name.c_str(), c.n,
                      c.min, c.p10, c.median, c.p90, c.max, c.mean);
        s += line;
    }
    std::snprintf(line, sizeof line, "histogram of %s over [%.6g, %.6g], %zu bins:", st.histogram_column.c_str(),
                  st.histogram_lo, st.histogram_hi, st.histogram.size());
    s += line;
    for (std::size_t n : st.histogram) s += " " + std::to_string(n);
    s += "\nwrote " + st.histogram_png.string() + "\n";
    return s;
}

std::string statsJson(const Stats& st) {
    json j;
    j["items"] = st.items;
    json cols = json::object();
    for (const ColumnStats& c : st.columns)
        cols[c.name] = {{"n", c.n},     {"min", c.min}, {"p10", c.p10},  {"median", c.median},
                        {"p90", c.p90}, {"max", c.max}, {"mean", c.mean}};
    j["columns"] = cols;
    j["histogram"] = {{"column", st.histogram_column},
                      {"lo", st.histogram_lo},
                      {"hi", st.histogram_hi},
                      {"counts", st.histogram},
                      {"png", st.histogram_png.string()}};
    return j.dump(2);
}

namespace {

struct Condition {
    std::string column, op;
    double value = 0;
    bool holds(double x) const {
        if (op == "<") return x < value;
        if (op == "<=") return x <= value;
        if (op == ">") return x > value;
        if (op == ">=") return x >= value;
        if (op == "==") return x == value;
        return x != value;
    }
};

std::vector<Condition> parseConditions(const std::string& text,
                                       const std::map<std::string, std::vector<double>>& columns) {
    std::vector<Condition> out;
    std::size_t start = 0;
    const auto bad = [&](const std::string& part, const std::string& why) {
        return core::Error("corpus: --select '" + core::printable(text, 80) + "': '" + core::printable(part, 40) +
                           "' " + why);
    };
    while (start <= text.size()) {
        const std::size_t comma = std::min(text.find(',', start), text.size());
        std::string part = text.substr(start, comma - start);
        part.erase(std::remove(part.begin(), part.end(), ' '), part.end());
        start = comma + 1;
        const std::size_t at = part.find_first_of("<>=!");
        if (part.empty() || at == std::string::npos || at == 0)
            throw bad(part, "is not COLUMN OP NUMBER; allowed OP <, <=, >, >=, ==, != and conditions joined by ','");
        Condition c;
        c.column = part.substr(0, at);
        const std::size_t after = part.find_first_not_of("<>=!", at);
        c.op = part.substr(at, after == std::string::npos ? std::string::npos : after - at);
        if (c.op != "<" && c.op != "<=" && c.op != ">" && c.op != ">=" && c.op != "==" && c.op != "!=")
            throw bad(part, "has operator '" + c.op + "'; allowed <, <=, >, >=, ==, !=");
        const std::string number = after == std::string::npos ? "" : part.substr(after);
        // Decimal notation only (from_chars' general format): no hex, as every number
        // option of the command line.
        const char* end = number.data() + number.size();
        const auto [stop, ec] = std::from_chars(number.data(), end, c.value, std::chars_format::general);
        if (number.empty() || ec != std::errc() || stop != end || !std::isfinite(c.value))
            throw bad(part, "does not end in a finite decimal number such as 2.5 or 1e3");
        if (!columns.count(c.column))
            throw bad(part, "names no column of the manifest; allowed " + columnList(columns));
        out.push_back(c);
    }
    return out;
}

}  // namespace

namespace {

// The manifest lines of the items `expression` holds for, `count` of them picked by a
// seeded shuffle and put back in index order. `count_name` is how the caller calls the count.
std::vector<json> pickItems(const std::vector<std::string>& lines, const std::string& expression, std::size_t count,
                            std::uint64_t seed, const std::string& count_name, SelectResult& r) {
    const std::vector<Condition> conditions = parseConditions(expression, columnsOf(lines));
    r.items = lines.size();
    std::vector<json> matching;
    for (const std::string& line : lines) {
        const auto values = manifestColumns(line);
        bool all = true;
        for (const Condition& c : conditions) {
            const auto it =
                std::find_if(values.begin(), values.end(), [&](const auto& p) { return p.first == c.column; });
            all = all && it != values.end() && c.holds(it->second);
        }
        if (all) matching.push_back(json::parse(line));
    }
    r.matching = matching.size();
    if (count < 1 || count > matching.size())
        throw core::Error("corpus: " + count_name + " " + std::to_string(count) + ": " +
                          std::to_string(matching.size()) + " of " + std::to_string(lines.size()) + " items match '" +
                          core::printable(expression, 80) + "'; allowed 1.." + std::to_string(matching.size()));
    SplitMix64 r64(mix64(seed));
    for (std::size_t i = 0; i < count; ++i) std::swap(matching[i], matching[i + r64.below(matching.size() - i)]);
    matching.resize(count);
    std::sort(matching.begin(), matching.end(), [](const json& a, const json& b) {
        return a["index"].get<std::size_t>() < b["index"].get<std::size_t>();
    });
    return matching;
}

// A picked item's cloud file: the one its manifest line describes, labelled per point.
SelectedItem selectedItem(const fs::path& dir, const json& m) {
    std::string cloud = "cloud.pcd";
    for (auto it = m["files"].begin(); it != m["files"].end(); ++it)
        if (it.key().rfind("cloud.", 0) == 0) cloud = it.key();
    const std::string id = m["id"].get<std::string>();
    return {id, fs::absolute(dir / "items").lexically_normal() / id / cloud};
}

}  // namespace

std::vector<SelectedItem> selectItems(const fs::path& dir, const std::string& expression, std::size_t count,
                                      std::uint64_t seed, const std::string& count_name) {
    platform::InputSet inputs;  // selectItems writes nothing
    const std::vector<std::string> lines = readManifest(dir, inputs);
    SelectResult r;
    std::vector<SelectedItem> out;
    for (const json& m : pickItems(lines, expression, count, seed, count_name, r)) out.push_back(selectedItem(dir, m));
    return out;
}

SelectResult selectTrials(const fs::path& dir, const SelectOptions& o) {
    if (!(o.time_limit_s > 0) || !std::isfinite(o.time_limit_s))
        throw core::Error("corpus: --time-limit-s " + core::shownNumber(o.time_limit_s) + ": allowed a number > 0");
    platform::InputSet inputs;
    const std::vector<std::string> lines = readManifest(dir, inputs);
    platform::checkWritableDestination(o.plan, inputs);  // before any work: not one of the inputs
    SelectResult r;
    const std::vector<json> matching = pickItems(lines, o.expression, o.count, o.seed, "--count", r);
    const fs::path plan_dir = fs::absolute(o.plan).lexically_normal().parent_path();
    const auto relative = [&](const fs::path& p) {
        const fs::path rel = p.lexically_relative(plan_dir);
        return (rel.empty() ? p : rel).generic_string();
    };
    json trials = json::array();
    for (const json& m : matching) {
        // A cloud trial (study/plan.hpp takes a cloud or a scene): the item's cloud is
        // the one its manifest line describes, labelled per point; its scene.json
        // replays it. The item id names the trial.
        const SelectedItem item = selectedItem(dir, m);
        trials.push_back(
            {{"cloud", relative(item.cloud)}, {"name", "item " + item.id}, {"time_limit_s", o.time_limit_s}});
    }
    json plan{{"trials", trials}, {"shuffle_seed", o.seed}};
    platform::writeFileAtomic(o.plan, plan.dump(2) + "\n");
    r.written = o.count;
    return r;
}

}  // namespace corpus
