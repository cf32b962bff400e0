// viewer/motion_prediction.hpp: the head's motion over the next moments, predicted from
// the last frames' poses, so a point source chooses nodes for where the eyes will be once
// those nodes are decoded and uploaded, not only for where they are now (a turning head
// finds the nodes ahead of it already resident). Pure maths on poses and matrices.
#pragma once
#include <render/orbit_camera.hpp>

#include <glm/gtc/quaternion.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include <cstddef>
#include <span>
#include <vector>

namespace viewer {

/// How far ahead the selection looks: the time from a node being wanted to its points on
/// the GPU (queued behind a few nodes for the decoding workers, a node of ~10^5 points
/// decoded and ordered in tens of ms, made resident at the next poll and uploaded over a
/// frame or two within the per-frame upload budget), about a quarter of a second.
constexpr double kSelectionLookahead_s = 0.25;

/// One frame's head pose (local frame) and when it was drawn.
struct HeadSample {
    double t_s = 0.0;
    glm::dvec3 position{0.0};
    glm::dquat orientation{1.0, 0.0, 0.0, 0.0};
};

/// The rigid motion (local frame: x -> R (x - p) + p + v t, p the newest position) the
/// head makes over `lookahead_s` if it keeps the linear and angular velocity it had from
/// the oldest to the newest of `history` (in time order). Identity with fewer than two
/// samples, no time between them, or no motion (a move under 1e-6 m and a turn under
/// 1e-6 rad between them count as none: a still head's poses differ by rounding).
glm::dmat4 predictedMotion(std::span<const HeadSample> history, double lookahead_s);

/// True when `motion` moves anything (not the identity within 1e-9).
bool moves(const glm::dmat4& motion);

/// The frusta a selection should see: each eye's (projection x view) and, when `motion`
/// moves, each eye's frustum after the head made `motion` (view x motion^-1): the union
/// covers where the eyes are and where they are predicted to be. `views` and
/// `projections` pair up.
std::vector<render::Frustum> widenedFrusta(std::span<const glm::dmat4> views, std::span<const glm::dmat4> projections,
                                           const glm::dmat4& motion);

/// The head pose of an eye's world-to-eye `view` (which may carry a uniform scale after
/// its rigid part): the eye's position and orientation in the local frame.
HeadSample headOfView(const glm::dmat4& view, double t_s);

}  // namespace viewer
