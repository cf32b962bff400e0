// metric/src/trace.cpp: camera poses along an operator's head trace (metric/trace.hpp).
#include <metric/trace.hpp>

#include <core/error.hpp>
#include <platform/safe_file.hpp>

namespace metric {

render::CameraPose cameraFromHead(const io::TraceRow& sample) {
    render::CameraPose pose;
    pose.eye = sample.head_world;
    pose.look_at = sample.head_world + sample.head_orientation * glm::dvec3(0.0, 0.0, -1.0);
    pose.up = glm::normalize(sample.head_orientation * glm::dvec3(0.0, 1.0, 0.0));
    return pose;
}

namespace {

// everyStep's rule: the first row, then each at least step_s after the last one kept.
bool keeps(bool first, double last_kept_s, double t_s, double step_s) { return first || t_s - last_kept_s >= step_s; }

}  // namespace

std::vector<io::TraceRow> everyStep(const std::vector<io::TraceRow>& samples, double step_s) {
    std::vector<io::TraceRow> kept;
    for (const io::TraceRow& s : samples)
        if (keeps(kept.empty(), kept.empty() ? 0.0 : kept.back().t_s, s.t_s, step_s)) kept.push_back(s);
    return kept;
}

std::vector<render::CameraPose> tracePoses(const std::filesystem::path& file, double step_s, std::size_t max_poses,
                                           std::size_t& samples) {
    std::vector<render::CameraPose> poses;
    double last_kept_s = 0.0;
    samples = 0;
    io::forEachTraceRow(file, [&](const io::TraceRow& row) {
        ++samples;
        if (!keeps(poses.empty(), last_kept_s, row.t_s, step_s)) return;
        if (poses.size() == max_poses)
            throw core::Error("metric: --trace " + core::printable(file.string(), 400) + ": more than " +
                              std::to_string(max_poses) + " samples are at least " + core::shownNumber(step_s) +
                              " s apart; allowed at most " + std::to_string(max_poses) +
                              " views (raise --trace-step-s)");
        poses.push_back(cameraFromHead(row));
        last_kept_s = row.t_s;
    });
    return poses;
}

}  // namespace metric
