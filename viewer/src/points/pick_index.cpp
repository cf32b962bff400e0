// viewer/src/points/pick_index.cpp: the pointer's cone pick over a nanoflann k-d tree.
#include <viewer/pick_index.hpp>

#include <core/error.hpp>
#include <platform/safe_file.hpp>

#include <nanoflann.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace viewer {

namespace {
/// nanoflann's view of a vector of float positions.
struct Positions {
    const std::vector<glm::vec3>* points = nullptr;
    std::size_t kdtree_get_point_count() const { return points->size(); }
    float kdtree_get_pt(std::size_t i, std::size_t dim) const { return (*points)[i][static_cast<int>(dim)]; }
    template <class Box>
    bool kdtree_get_bbox(Box&) const {
        return false;
    }
};
using KdTree =
    nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<float, Positions>, Positions, 3, std::uint32_t>;

/// The points a sphere query reaches are tested against the cone here, keeping the one
/// nearest the apex, so no list of candidates is ever built.
struct ConeResult {
    using DistanceType = float;
    using IndexType = std::uint32_t;
    const std::vector<glm::vec3>* points = nullptr;
    glm::dvec3 origin{0.0}, direction{0.0};  // direction unit length
    double cos2_angle = 1.0;                 // cos^2 of the cone's half angle
    float radius2 = 0.0f;                    // of the sphere query
    double best_distance2 = std::numeric_limits<double>::infinity();
    std::optional<std::size_t> best;

    void init() {}
    void sort() {}
    std::size_t size() const { return best ? 1 : 0; }
    bool full() const { return true; }
    float worstDist() const { return radius2; }
    bool addPoint(float, std::uint32_t index) {
        const glm::dvec3 v = glm::dvec3((*points)[index]) - origin;
        const double along = glm::dot(v, direction);
        if (along <= 0.0) return true;
        const double d2 = glm::dot(v, v);
        // Inside the cone: angle(v, direction) <= half angle, i.e. along^2 >= cos^2 * |v|^2.
        if (along * along >= cos2_angle * d2 && d2 < best_distance2) {
            best_distance2 = d2;
            best = index;
        }
        return true;
    }
};

/// [t_enter, t_exit] of the ray inside the box (slab test); false when it misses.
bool clipToBox(const glm::dvec3& o, const glm::dvec3& d, const glm::dvec3& lo, const glm::dvec3& hi, double& t_enter,
               double& t_exit) {
    for (int axis = 0; axis < 3; ++axis) {
        if (std::abs(d[axis]) < 1e-300) {
            if (o[axis] < lo[axis] || o[axis] > hi[axis]) return false;
            continue;
        }
        double a = (lo[axis] - o[axis]) / d[axis], b = (hi[axis] - o[axis]) / d[axis];
        if (a > b) std::swap(a, b);
        t_enter = std::max(t_enter, a);
        t_exit = std::min(t_exit, b);
    }
    return t_enter <= t_exit;
}
}  // namespace

struct PickIndex::Tree {
    Positions adaptor;
    KdTree tree;
    explicit Tree(const std::vector<glm::vec3>& points)
        : adaptor{&points}, tree(3, adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(16)) {}
};
struct PickIndex::TargetTree : PickIndex::Tree {
    using Tree::Tree;
};

void validate(const PickOptions& o) {
    if (!(o.angle_deg > 0.0 && o.angle_deg <= 10.0))
        throw core::Error("view: --pick-angle " + core::shownNumber(o.angle_deg) + ": allowed (0, 10] degrees");
    if (!(o.max_range_m > 0.0 && std::isfinite(o.max_range_m)))
        throw core::Error("view: pick range " + core::shownNumber(o.max_range_m) + ": allowed a finite value > 0 m");
}

PickIndex::PickIndex(std::span<const core::CloudPoint> points) {
    positions_.reserve(points.size());
    labels_.reserve(points.size());
    heights_.reserve(points.size());
    lo_ = glm::dvec3(std::numeric_limits<double>::infinity());
    hi_ = -lo_;
    target_lo_ = lo_;
    target_hi_ = hi_;
    for (const core::CloudPoint& p : points) {
        positions_.push_back(p.position);
        labels_.push_back(p.label);
        heights_.push_back(p.height_above_ground_m);
        if (p.label == core::Role::Target) {
            targets_.push_back(p.position);
            target_lo_ = glm::min(target_lo_, glm::dvec3(p.position));
            target_hi_ = glm::max(target_hi_, glm::dvec3(p.position));
        }
        lo_ = glm::min(lo_, glm::dvec3(p.position));
        hi_ = glm::max(hi_, glm::dvec3(p.position));
    }
    tree_ = std::make_unique<Tree>(positions_);
    if (!targets_.empty()) target_tree_ = std::make_unique<TargetTree>(targets_);
}

PickIndex::~PickIndex() = default;

PickHit PickIndex::hitAt(std::size_t i, double distance_m) const {
    PickHit h;
    h.index = i;
    h.local = glm::dvec3(positions_[i]);
    h.distance_m = distance_m;
    h.label = labels_[i];
    h.height_above_ground_m = heights_[i];
    return h;
}

std::optional<PickHit> PickIndex::pick(const glm::dvec3& origin, const glm::dvec3& direction,
                                       const PickOptions& options) const {
    last_queries_ = 0;
    const double length = glm::length(direction);
    if (positions_.empty() || !(length > 0.0) || !std::isfinite(length)) return std::nullopt;
    const glm::dvec3 d = direction / length;
    const double angle_rad = options.angle_deg * std::numbers::pi / 180.0;
    const double tan_a = std::tan(angle_rad);
    // The cone's points lie within tan_a * t of the axis at depth t: clip the walk to the
    // bounds grown by that much at the box's far end.
    double t = 0.0, t_end = options.max_range_m;
    double far_m = 0.0;  // no point of the box is further than this from the origin
    for (int corner = 0; corner < 8; ++corner) {
        const glm::dvec3 c((corner & 1) ? hi_.x : lo_.x, (corner & 2) ? hi_.y : lo_.y, (corner & 4) ? hi_.z : lo_.z);
        far_m = std::max(far_m, glm::length(c - origin));
    }
    const glm::dvec3 grow(tan_a * std::min(far_m, options.max_range_m) + 1e-3);
    if (!clipToBox(origin, d, lo_ - grow, hi_ + grow, t, t_end)) return std::nullopt;
    t = std::max(t, 0.0);

    ConeResult result;
    result.points = &positions_;
    result.origin = origin;
    result.direction = d;
    result.cos2_angle = std::cos(angle_rad) * std::cos(angle_rad);
    constexpr double kMinSegmentM = 0.05;
    // Segment [t, t1]: the cone's slice there lies within the sphere about its middle
    // point whose radius reaches the slice's far rim. Segments twice the cone's radius
    // long keep each sphere about 1.4 times the slice's width.
    while (t <= t_end && t * t < result.best_distance2) {
        const double t1 = t + std::max(kMinSegmentM, 2.0 * tan_a * t);
        const double half = 0.5 * (t1 - t), rim = tan_a * t1;
        const glm::vec3 centre(origin + d * (t + half));
        result.radius2 = static_cast<float>(half * half + rim * rim) * 1.0001f + 1e-6f;
        tree_->tree.findNeighbors(result, &centre.x, nanoflann::SearchParameters(0.0f, false));
        ++last_queries_;
        t = t1;
    }
    if (!result.best) return std::nullopt;
    return hitAt(*result.best, std::sqrt(result.best_distance2));
}

std::optional<PickHit> PickIndex::pickByScan(const glm::dvec3& origin, const glm::dvec3& direction,
                                             const PickOptions& options) const {
    const double length = glm::length(direction);
    if (!(length > 0.0) || !std::isfinite(length)) return std::nullopt;
    ConeResult result;
    result.points = &positions_;
    result.origin = origin;
    result.direction = direction / length;
    const double c = std::cos(options.angle_deg * std::numbers::pi / 180.0);
    result.cos2_angle = c * c;
    for (std::size_t i = 0; i < positions_.size(); ++i) {
        const glm::dvec3 v = glm::dvec3(positions_[i]) - origin;
        if (glm::dot(v, v) <= options.max_range_m * options.max_range_m)
            result.addPoint(0.0f, static_cast<std::uint32_t>(i));
    }
    if (!result.best) return std::nullopt;
    return hitAt(*result.best, std::sqrt(result.best_distance2));
}

std::optional<double> PickIndex::nearestTargetDistance(const glm::dvec3& p) const {
    if (!target_tree_) return std::nullopt;
    // The query is relative to the local frame, in float like the stored points; the
    // distance is recomputed in double from the point found.
    const glm::vec3 q(p);
    std::uint32_t index = 0;
    float d2 = 0.0f;
    nanoflann::KNNResultSet<float, std::uint32_t> result(1);
    result.init(&index, &d2);
    target_tree_->tree.findNeighbors(result, &q.x);
    return glm::length(glm::dvec3(targets_[index]) - p);
}

// --- PickSet ---------------------------------------------------------------------------------
void PickSet::add(std::shared_ptr<const PickIndex> index, int level) {
    size_ += index->size();
    indexes_.push_back(std::move(index));
    levels_.push_back(level);
}

std::optional<PickHit> PickSet::pick(const glm::dvec3& origin, const glm::dvec3& direction,
                                     const PickOptions& options) const {
    std::optional<PickHit> best;
    for (std::size_t i = 0; i < indexes_.size(); ++i) {
        std::optional<PickHit> hit = indexes_[i]->pick(origin, direction, options);
        if (hit && (!best || hit->distance_m < best->distance_m)) {
            hit->node = i;
            hit->level = levels_[i];
            best = hit;
        }
    }
    return best;
}

std::optional<double> PickSet::nearestTargetDistance(const glm::dvec3& p) const {
    std::optional<double> best;
    for (const auto& index : indexes_)
        if (const auto d = index->nearestTargetDistance(p); d && (!best || *d < *best)) best = d;
    return best;
}

std::optional<glm::dvec3> PickSet::targetCentre() const {
    std::optional<glm::dvec3> lo, hi;
    for (const auto& index : indexes_)
        if (index->hasTargets()) {
            lo = lo ? glm::min(*lo, index->targetLow()) : index->targetLow();
            hi = hi ? glm::max(*hi, index->targetHigh()) : index->targetHigh();
        }
    if (!lo) return std::nullopt;
    return (*lo + *hi) * 0.5;
}

bool PickSet::hasTargets() const {
    for (const auto& index : indexes_)
        if (index->hasTargets()) return true;
    return false;
}

}  // namespace viewer
