// metric/src/trace.cpp: camera poses along an operator's head trace (metric/trace.hpp).
#include <metric/trace.hpp>

namespace metric {

render::CameraPose cameraFromHead(const io::TraceRow& sample) {
    render::CameraPose pose;
    pose.eye = sample.head_world;
    pose.look_at = sample.head_world + sample.head_orientation * glm::dvec3(0.0, 0.0, -1.0);
    pose.up = glm::normalize(sample.head_orientation * glm::dvec3(0.0, 1.0, 0.0));
    return pose;
}

std::vector<io::TraceRow> everyStep(const std::vector<io::TraceRow>& samples, double step_s) {
    std::vector<io::TraceRow> kept;
    for (const io::TraceRow& s : samples)
        if (kept.empty() || s.t_s - kept.back().t_s >= step_s) kept.push_back(s);
    return kept;
}

}  // namespace metric
