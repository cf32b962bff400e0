// viewer/src/points/motion_prediction.cpp: constant-velocity head prediction and the widened
// selection frusta (motion_prediction.hpp).
#include <viewer/motion_prediction.hpp>

#include <glm/gtc/matrix_transform.hpp>

#include <cassert>
#include <cmath>

namespace viewer {

glm::dmat4 predictedMotion(std::span<const HeadSample> history, double lookahead_s) {
    if (history.size() < 2) return glm::dmat4(1.0);
    const HeadSample& a = history.front();
    const HeadSample& b = history.back();
    const double dt_s = b.t_s - a.t_s;
    if (!(dt_s > 0.0) || !(lookahead_s > 0.0)) return glm::dmat4(1.0);
    const double k = lookahead_s / dt_s;
    // A still head's poses differ by rounding at most: motion under a micrometre and a
    // microradian between the samples is none, so a still view selects as if unpredicted.
    constexpr double kStill_m = 1e-6, kStill_rad = 1e-6;
    const glm::dvec3 moved = b.position - a.position;
    const glm::dvec3 shift = glm::length(moved) < kStill_m ? glm::dvec3(0.0) : moved * k;
    // The rotation from a to b, in the local frame, scaled in angle by k.
    glm::dquat step = glm::normalize(b.orientation * glm::inverse(a.orientation));
    if (step.w < 0.0) step = -step;  // the short way round
    const double angle = 2.0 * std::atan2(glm::length(glm::dvec3(step.x, step.y, step.z)), step.w);
    glm::dmat4 rotate(1.0);
    if (angle >= kStill_rad) {
        const glm::dvec3 axis = glm::normalize(glm::dvec3(step.x, step.y, step.z));
        rotate = glm::rotate(glm::dmat4(1.0), angle * k, axis);
    }
    return glm::translate(glm::dmat4(1.0), b.position + shift) * rotate * glm::translate(glm::dmat4(1.0), -b.position);
}

bool moves(const glm::dmat4& motion) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (std::abs(motion[c][r] - (c == r ? 1.0 : 0.0)) > 1e-9) return true;
    return false;
}

std::vector<render::Frustum> widenedFrusta(std::span<const glm::dmat4> views, std::span<const glm::dmat4> projections,
                                           const glm::dmat4& motion) {
    assert(views.size() == projections.size());
    std::vector<render::Frustum> out;
    for (std::size_t i = 0; i < views.size(); ++i)
        out.push_back(render::Frustum::fromMatrix(projections[i] * views[i]));
    if (!moves(motion)) return out;
    const glm::dmat4 back = glm::inverse(motion);
    for (std::size_t i = 0; i < views.size(); ++i)
        out.push_back(render::Frustum::fromMatrix(projections[i] * views[i] * back));
    return out;
}

HeadSample headOfView(const glm::dmat4& view, double t_s) {
    const glm::dmat4 eye = glm::inverse(view);
    glm::dmat3 r(eye);
    for (int c = 0; c < 3; ++c) r[c] = glm::normalize(r[c]);  // drop the zoom's scale
    return {t_s, glm::dvec3(eye[3]), glm::normalize(glm::quat_cast(r))};
}

}  // namespace viewer
