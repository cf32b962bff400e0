// viewer/src/world_zoom.cpp: the zoom similarity and its two-handed grab.
#include <viewer/world_zoom.hpp>

#include <algorithm>
#include <cmath>

namespace viewer {

void WorldZoom::scaleAbout(const glm::dvec3& pivot, double new_scale) {
    if (!std::isfinite(new_scale) || !(new_scale > 0.0)) return;
    const glm::dvec3 fixed = apply(pivot);
    scale_ = std::clamp(new_scale, options_.min_scale, options_.max_scale);
    offset_ = fixed - pivot / scale_;
}

void WorldZoom::beginGrab(const glm::dvec3& left, const glm::dvec3& right) {
    const double d = glm::length(right - left);
    if (!(d >= 0.01)) return;
    grabbing_ = true;
    grab_scale_ = scale_;
    grab_distance_m_ = d;
    grab_point_ = apply(0.5 * (left + right));
}

void WorldZoom::updateGrab(const glm::dvec3& left, const glm::dvec3& right) {
    if (!grabbing_) return;
    const double d = glm::length(right - left);
    if (!(d >= 1e-4) || !std::isfinite(d)) return;
    scale_ = std::clamp(grab_scale_ * d / grab_distance_m_, options_.min_scale, options_.max_scale);
    offset_ = grab_point_ - 0.5 * (left + right) / scale_;
}

void WorldZoom::reset() {
    scale_ = 1.0;
    offset_ = glm::dvec3(0.0);
    grabbing_ = false;
}

}  // namespace viewer
