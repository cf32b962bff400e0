// metric/src/trace.cpp: strict reading of a study's head trace (metric/trace.hpp).
#include <metric/trace.hpp>

#include <core/error.hpp>
#include <platform/safe_file.hpp>

#include <array>
#include <charconv>
#include <cmath>
#include <string>

namespace metric {
namespace {

constexpr std::array<std::string_view, 8> kColumns = {"t_s",     "head_x",  "head_y",  "head_z",
                                                      "head_qw", "head_qx", "head_qy", "head_qz"};

std::vector<std::string_view> splitFields(std::string_view line) {
    std::vector<std::string_view> fields;
    std::size_t start = 0;
    while (true) {
        const std::size_t comma = line.find(',', start);
        fields.push_back(line.substr(start, comma == std::string_view::npos ? std::string_view::npos : comma - start));
        if (comma == std::string_view::npos) break;
        start = comma + 1;
    }
    return fields;
}

}  // namespace

std::vector<HeadSample> parseTrace(std::string_view text, const std::filesystem::path& name) {
    const std::string where = "trace: " + name.string() + ": ";
    auto fail = [&](std::size_t line, std::string_view column, const std::string& what) {
        throw core::Error(where + "line " + std::to_string(line) +
                            (column.empty() ? std::string() : ", column " + std::string(column)) + ": " + what);
    };
    std::vector<HeadSample> samples;
    std::size_t line_no = 0, pos = 0, header_fields = 0;
    while (pos < text.size()) {
        std::size_t end = text.find('\n', pos);
        if (end == std::string_view::npos) end = text.size();
        std::string_view line = text.substr(pos, end - pos);
        pos = end + 1;
        ++line_no;
        if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
        const std::vector<std::string_view> fields = splitFields(line);
        if (line_no == 1) {
            for (std::size_t k = 0; k < kColumns.size(); ++k)
                if (k >= fields.size() || fields[k] != kColumns[k])
                    fail(1, "", "header column " + std::to_string(k + 1) + " is '" +
                                    core::printable(k < fields.size() ? fields[k] : std::string_view(), 40) +
                                    "'; allowed a header starting t_s,head_x,head_y,head_z,head_qw,head_qx,"
                                    "head_qy,head_qz");
            header_fields = fields.size();
            continue;
        }
        if (line.empty()) fail(line_no, "", "empty line; allowed one sample per line");
        if (fields.size() != header_fields)
            fail(line_no, "", std::to_string(fields.size()) + " fields; allowed " + std::to_string(header_fields) +
                                  " (as the header)");
        double v[8];
        for (std::size_t k = 0; k < kColumns.size(); ++k) {
            const std::string_view f = fields[k];
            const auto [ptr, ec] = std::from_chars(f.data(), f.data() + f.size(), v[k]);
            if (f.empty() || ec != std::errc() || ptr != f.data() + f.size() || !std::isfinite(v[k]))
                fail(line_no, kColumns[k], "'" + core::printable(f, 40) + "' is not a finite number");
        }
        HeadSample s;
        s.t_s = v[0];
        if (s.t_s < 0.0) fail(line_no, "t_s", "negative; allowed seconds >= 0");
        if (!samples.empty() && s.t_s < samples.back().t_s)
            fail(line_no, "t_s", "decreases (" + std::to_string(samples.back().t_s) + " before); allowed times in order");
        s.head_world = {v[1], v[2], v[3]};
        if (!(std::abs(v[1]) <= 1e9 && std::abs(v[2]) <= 1e9 && std::abs(v[3]) <= 1e9))
            fail(line_no, "head_x", "out of range; allowed world coordinates within 1e9 m");
        const glm::dquat q(v[4], v[5], v[6], v[7]);
        const double norm = glm::length(q);
        if (!(std::abs(norm - 1.0) <= 1e-3))
            fail(line_no, "head_qw", "quaternion norm " + std::to_string(norm) + "; allowed a unit quaternion (within 1e-3)");
        s.head_orientation = q / norm;
        samples.push_back(s);
    }
    if (line_no == 0) fail(1, "", "empty file; allowed a header and samples");
    if (samples.empty()) fail(line_no, "", "no samples after the header");
    return samples;
}

std::vector<HeadSample> readTrace(const std::filesystem::path& file) {
    const std::string text = platform::readTextFile(file, kMaxTraceBytes, "trace: " + file.string() + ":");
    return parseTrace(text, file);
}

render::CameraPose cameraFromHead(const HeadSample& sample) {
    render::CameraPose pose;
    pose.eye = sample.head_world;
    pose.look_at = sample.head_world + sample.head_orientation * glm::dvec3(0.0, 0.0, -1.0);
    pose.up = glm::normalize(sample.head_orientation * glm::dvec3(0.0, 1.0, 0.0));
    return pose;
}

std::vector<HeadSample> everyStep(const std::vector<HeadSample>& samples, double step_s) {
    std::vector<HeadSample> kept;
    for (const HeadSample& s : samples)
        if (kept.empty() || s.t_s - kept.back().t_s >= step_s) kept.push_back(s);
    return kept;
}

}  // namespace metric
