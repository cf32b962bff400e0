// bench/src/common.hpp: what every benchmark program shares: clocks, statistics, number
// formatting, the machine line, the source tree, shell quoting, and rewriting one section
// of BENCHMARKS.md.
#pragma once
#include <chrono>
#include <filesystem>
#include <string>
#include <vector>

namespace bench {

using Clock = std::chrono::steady_clock;
/// Wall time since t0, in seconds / in milliseconds.
double secondsSince(Clock::time_point t0);
double msSince(Clock::time_point t0);

/// Median of the samples; NaN when there are none.
double median(std::vector<double> samples);
/// The q-quantile (0..1, nearest rank) of the samples; NaN when there are none.
double quantile(std::vector<double> samples, double q);
/// printf-style formatting of one number ("%.2f").
std::string fmt(const char* format, double v);

/// The median of repeated measurements with their smallest and largest value.
struct Spread {
    double min = 0, median = 0, max = 0;
    std::size_t n = 0;  // samples
};
/// min, median, max of the samples; all NaN (n = 0) when there are none.
Spread spread(const std::vector<double>& samples);
/// "median [min..max]" with `format` for each number ("%.3f"); the median alone when
/// there are fewer than 2 samples (no spread to show).
std::string fmtSpread(const char* format, const Spread& s);
/// Whether the [min, max] ranges of two measurements overlap: a ratio of their medians is
/// then within the run-to-run spread. False when either has fewer than 2 samples.
bool withinSpread(const Spread& a, const Spread& b);
/// " (within spread)" when withinSpread(a, b), else "".
std::string spreadNote(const Spread& a, const Spread& b);
/// The CPU's model name from /proc/cpuinfo, or "unknown CPU".
std::string cpuName();
/// "YYYY-MM-DD HH:MM UTC" now.
std::string utcNow();
/// The source checkout this program was built from (CMake's source folder, a compile
/// definition): where scripts/, tests/, assets/ and docs/ are.
std::filesystem::path sourceRoot();
/// `s` in single quotes for /bin/sh, embedded quotes escaped.
std::string shellQuote(const std::string& s);
/// The whole file as a string; empty if it cannot be read.
std::string readText(const std::filesystem::path& path);

/// A bench's working folder: `given` when the user named one (kept afterwards), else a
/// folder of its own under the system's temporary folder, named `prefix` and the process
/// id, removed with everything in it when this object goes.
class WorkFolder {
  public:
    WorkFolder(const std::filesystem::path& given, const std::string& prefix);
    ~WorkFolder();
    WorkFolder(const WorkFolder&) = delete;
    WorkFolder& operator=(const WorkFolder&) = delete;
    const std::filesystem::path& path() const { return path_; }

  private:
    std::filesystem::path path_;
    bool own_ = false;
};

/// Replaces the section that starts with `heading` (a "## ..." line) up to the next
/// "## " heading with `section`, or appends it; writes atomically. A missing file
/// starts as "# Benchmarks".
void replaceMarkdownSection(const std::filesystem::path& path, const std::string& heading, const std::string& section);
/// Replaces everything before the first "## " section with `header`; writes atomically.
void replaceMarkdownHeader(const std::filesystem::path& path, const std::string& header);

}  // namespace bench
