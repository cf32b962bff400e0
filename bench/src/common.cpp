// bench/src/common.cpp: see common.hpp.
#include "common.hpp"

#include <platform/atomic_file.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <sstream>
#include <system_error>

#include <unistd.h>

namespace bench {

double secondsSince(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

double msSince(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

double median(std::vector<double> v) {
    if (v.empty()) return std::nan("");
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

double quantile(std::vector<double> v, double q) {
    if (v.empty()) return std::nan("");
    std::sort(v.begin(), v.end());
    return v[std::min(v.size() - 1, std::size_t(q * double(v.size() - 1) + 0.5))];
}

std::string fmt(const char* format, double v) {
    char b[64];
    std::snprintf(b, sizeof b, format, v);
    return b;
}

Spread spread(const std::vector<double>& samples) {
    Spread s;
    s.n = samples.size();
    if (samples.empty()) {
        s.min = s.median = s.max = std::nan("");
        return s;
    }
    const auto [lo, hi] = std::minmax_element(samples.begin(), samples.end());
    s.min = *lo;
    s.max = *hi;
    s.median = median(samples);
    return s;
}

std::string fmtSpread(const char* format, const Spread& s) {
    if (s.n < 2) return fmt(format, s.median);
    return fmt(format, s.median) + " [" + fmt(format, s.min) + ".." + fmt(format, s.max) + "]";
}

bool withinSpread(const Spread& a, const Spread& b) { return a.n >= 2 && b.n >= 2 && a.min <= b.max && b.min <= a.max; }

std::string spreadNote(const Spread& a, const Spread& b) { return withinSpread(a, b) ? " (within spread)" : ""; }

std::string cpuName() {
    std::ifstream in("/proc/cpuinfo");
    std::string line;
    while (std::getline(in, line))
        if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
    return "unknown CPU";
}

std::string utcNow() {
    const std::time_t now = std::time(nullptr);
    char date[64];
    std::strftime(date, sizeof date, "%Y-%m-%d %H:%M UTC", std::gmtime(&now));
    return date;
}

std::filesystem::path sourceRoot() { return LADARVR_SOURCE_DIR; }

std::string shellQuote(const std::string& s) {
    std::string q = "'";
    for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

std::string readText(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

void replaceMarkdownSection(const std::filesystem::path& path, const std::string& heading, const std::string& section) {
    std::string text = std::filesystem::exists(path) ? readText(path) : std::string("# Benchmarks\n");
    const std::size_t start = text.find(heading);
    if (start == std::string::npos) {
        if (!text.empty() && text.back() != '\n') text += '\n';
        text += "\n" + section;
    } else {
        std::size_t end = text.find("\n## ", start + heading.size());
        end = end == std::string::npos ? text.size() : end + 1;
        text = text.substr(0, start) + section + (end < text.size() ? "\n" + text.substr(end) : "");
    }
    platform::writeFileAtomic(path, text);
}

void replaceMarkdownHeader(const std::filesystem::path& path, const std::string& header) {
    const std::string text = std::filesystem::exists(path) ? readText(path) : std::string();
    const std::size_t first = text.rfind("## ", 0) == 0 ? 0 : text.find("\n## ");
    platform::writeFileAtomic(path,
                              header + (first == std::string::npos ? "" : "\n" + text.substr(first + (first ? 1 : 0))));
}

WorkFolder::WorkFolder(const std::filesystem::path& given, const std::string& prefix)
    : path_(given.empty() ? std::filesystem::temp_directory_path() / (prefix + std::to_string(::getpid())) : given),
      own_(given.empty()) {
    std::filesystem::create_directories(path_);
}

WorkFolder::~WorkFolder() {
    std::error_code ec;
    if (own_) std::filesystem::remove_all(path_, ec);
}

}  // namespace bench
