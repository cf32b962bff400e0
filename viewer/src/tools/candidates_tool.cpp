// viewer/src/tools/candidates_tool.cpp: candidate boxes, picked by the pointer's ray.
#include "tools/candidates_tool.hpp"

#include "ui/panel.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace viewer {

namespace {
/// The box's axes in the local frame: x along yaw, y across, z up.
void axes(double yaw_deg, glm::dvec3& ax, glm::dvec3& ay) {
    const double a = yaw_deg * std::numbers::pi / 180.0;
    ax = {std::cos(a), std::sin(a), 0.0};
    ay = {-std::sin(a), std::cos(a), 0.0};
}
}  // namespace

std::optional<double> rayBoxDistance(const LocalRay& ray, const glm::dvec3& centre, const glm::dvec3& size_m,
                                     double yaw_deg) {
    glm::dvec3 ax, ay;
    axes(yaw_deg, ax, ay);
    const glm::dvec3 rel = ray.origin - centre;
    // The ray in the box's own frame, then a slab test against +-size/2.
    const glm::dvec3 o(glm::dot(rel, ax), glm::dot(rel, ay), rel.z);
    const glm::dvec3 d(glm::dot(ray.direction, ax), glm::dot(ray.direction, ay), ray.direction.z);
    double t0 = 0.0, t1 = std::numeric_limits<double>::infinity();
    for (int i = 0; i < 3; ++i) {
        const double half = 0.5 * size_m[i];
        if (std::abs(d[i]) < 1e-15) {
            if (std::abs(o[i]) > half) return std::nullopt;
            continue;
        }
        double a = (-half - o[i]) / d[i], b = (half - o[i]) / d[i];
        if (a > b) std::swap(a, b);
        t0 = std::max(t0, a);
        t1 = std::min(t1, b);
        if (t0 > t1) return std::nullopt;
    }
    return t0;
}

bool boxMeetsCut(const CutVolume& cut, const glm::dvec3& centre, const glm::dvec3& size_m, double yaw_deg) {
    if (!cut.enabled) return true;
    glm::dvec3 ax, ay;
    axes(yaw_deg, ax, ay);
    // The sphere's centre in the box's own frame; the box's nearest point to it within the sphere.
    const glm::dvec3 rel = cut.centre_local - centre;
    const glm::dvec3 c(glm::dot(rel, ax), glm::dot(rel, ay), rel.z);
    double d2 = 0.0;
    for (int i = 0; i < 3; ++i) {
        const double half = 0.5 * size_m[i];
        const double outside = std::max(std::abs(c[i]) - half, 0.0);
        d2 += outside * outside;
    }
    return d2 <= cut.radius_m * cut.radius_m;
}

void CandidatesTool::set(std::vector<core::Candidate> candidates, const glm::dvec3& origin) {
    candidates_ = std::move(candidates);
    verdicts_.assign(candidates_.size(), Verdict::Unreviewed);
    origin_ = origin;
    pointed_.reset();
    cut_ = {};
}

bool CandidatesTool::shown(std::size_t i) const {
    const core::Candidate& c = candidates_[i];
    return boxMeetsCut(cut_, c.centre_world - origin_, c.size_m, c.yaw_deg);
}

void CandidatesTool::update(const std::optional<LocalRay>& ray, const CutVolume& cut) {
    pointed_.reset();
    cut_ = cut;
    if (!ray) return;
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < candidates_.size(); ++i) {
        if (!shown(i)) continue;
        const core::Candidate& c = candidates_[i];
        if (const auto t = rayBoxDistance(*ray, c.centre_world - origin_, c.size_m, c.yaw_deg); t && *t < best) {
            best = *t;
            pointed_ = i;
        }
    }
}

std::optional<std::size_t> CandidatesTool::setVerdict(const std::string& id, Verdict verdict) {
    for (std::size_t i = 0; i < candidates_.size(); ++i)
        if (candidates_[i].id == id) {
            verdicts_[i] = verdict;
            return i;
        }
    return std::nullopt;
}

std::optional<std::size_t> CandidatesTool::decide(Verdict verdict) {
    if (!pointed_) return std::nullopt;
    verdicts_[*pointed_] = verdict;
    return pointed_;
}

void CandidatesTool::draw(OverlayList& out, bool highlight) const {
    for (std::size_t i = 0; i < candidates_.size(); ++i) {
        if (!shown(i)) continue;
        const core::Candidate& c = candidates_[i];
        glm::vec4 colour;
        switch (verdicts_[i]) {
            case Verdict::Confirmed: colour = {0.1f, 1.0f, 0.2f, 1.0f}; break;
            case Verdict::Rejected: colour = {0.5f, 0.5f, 0.5f, 0.6f}; break;
            default: {  // score 1 red, 0 yellow
                const float s = static_cast<float>(std::clamp(c.score, 0.0, 1.0));
                colour = {1.0f, 1.0f - s, 0.0f, highlight ? 1.0f : 0.7f};
            }
        }
        if (pointed_ && *pointed_ == i) colour = {0.2f, 0.8f, 1.0f, 1.0f};
        glm::dvec3 ax, ay;
        axes(c.yaw_deg, ax, ay);
        const glm::dvec3 centre = c.centre_world - origin_;
        auto corner = [&](int k) {
            return centre + ax * (((k & 1) ? 0.5 : -0.5) * c.size_m.x) + ay * (((k & 2) ? 0.5 : -0.5) * c.size_m.y) +
                   glm::dvec3(0, 0, ((k & 4) ? 0.5 : -0.5) * c.size_m.z);
        };
        for (int k = 0; k < 8; ++k)
            for (int bit : {1, 2, 4})
                if (!(k & bit)) out.line(corner(k), corner(k | bit), colour);
    }
}

nlohmann::json CandidatesTool::log() const {
    nlohmann::json list = nlohmann::json::array();
    for (std::size_t i = 0; i < candidates_.size(); ++i)
        list.push_back({{"id", candidates_[i].id}, {"verdict", verdictName(verdicts_[i])}});
    return list;
}

void CandidatesTool::describe(PanelView& v) {
    v.highlight_candidates = &highlight_;
    v.candidates = candidates_.size();
}

}  // namespace viewer
