// viewer/pick_index.hpp: picking a cloud point with a ray (the operator's laser pointer).
//
// The picked point is the cloud point nearest the ray's origin among those within an
// angular radius of the ray (a thin cone), so a pointer that grazes an edge still finds
// the surface and a point behind it is never chosen over one in front. The points sit in
// a k-d tree (nanoflann); a pick walks the cone from its apex outwards in short
// segments, each covered by one sphere query, and stops once no later segment can hold a
// nearer point: a pick touches the points near the ray, not the whole cloud. Pure maths,
// no GL. The frame loop keeps one index per node of its point source (point_source.hpp)
// in a PickSet, built on a worker thread, and picks the nearest of the nodes' picks.
#pragma once
#include <core/point_cloud.hpp>

#include <glm/vec3.hpp>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <vector>

namespace viewer {

struct PickOptions {
    double angle_deg = 0.5;        // angular radius of the cone around the ray, (0, 10]
    double max_range_m = 20000.0;  // nothing further than this from the origin is picked
};

/// Throws core::Error("view: --pick-angle X: allowed (0, 10] degrees") when out of range.
void validate(const PickOptions& o);

struct PickHit {
    std::size_t index = 0;    // into the points the index was built from
    std::size_t node = 0;     // PickSet: which of its indexes (in the order added)
    int level = -1;           // PickSet: the octree level (depth) of that node; -1 when not known
    glm::dvec3 local{0.0};    // the point, cloud local frame
    double distance_m = 0.0;  // from the ray's origin
    core::Role label = core::Role::Environment;
    float height_above_ground_m = 0.0f;
    /// A survey's ASPRS class (a cloud from elsewhere, its classes kept): the pick panel
    /// names it in place of the role our own clouds carry. Set by the viewer.
    std::optional<std::uint8_t> asprs_class;
};

class PickIndex {
  public:
    /// Builds the k-d tree over the points' positions (cloud local frame). Keeps positions,
    /// labels and heights above ground (21 bytes a point), not the whole points.
    explicit PickIndex(std::span<const core::CloudPoint> points);
    ~PickIndex();
    PickIndex(const PickIndex&) = delete;
    PickIndex& operator=(const PickIndex&) = delete;

    std::size_t size() const { return positions_.size(); }
    /// The pick of the ray from `origin` along `direction` (need not be unit length; a zero
    /// direction picks nothing), local frame. Never throws.
    std::optional<PickHit> pick(const glm::dvec3& origin, const glm::dvec3& direction,
                                const PickOptions& options = {}) const;
    /// The same answer by testing every point (for tests and the benchmark's baseline).
    std::optional<PickHit> pickByScan(const glm::dvec3& origin, const glm::dvec3& direction,
                                      const PickOptions& options = {}) const;
    /// Distance from `p` to the nearest point labelled target; none without target points.
    std::optional<double> nearestTargetDistance(const glm::dvec3& p) const;
    /// Whether any point is labelled target.
    bool hasTargets() const { return !targets_.empty(); }
    /// The bounds of the points labelled target (local frame); meaningless without them.
    const glm::dvec3& targetLow() const { return target_lo_; }
    const glm::dvec3& targetHigh() const { return target_hi_; }
    /// Sphere queries the last pick made (for the benchmark's report).
    std::size_t lastQueries() const { return last_queries_; }

    struct Tree;
    struct TargetTree;

  private:
    PickHit hitAt(std::size_t i, double distance_m) const;

    std::vector<glm::vec3> positions_;
    std::vector<core::Role> labels_;
    std::vector<float> heights_;
    std::vector<glm::vec3> targets_;
    glm::dvec3 lo_{0.0}, hi_{0.0};                // bounds of the positions
    glm::dvec3 target_lo_{0.0}, target_hi_{0.0};  // bounds of the targets
    std::unique_ptr<Tree> tree_;
    std::unique_ptr<TargetTree> target_tree_;
    mutable std::size_t last_queries_ = 0;
};

/// One PickIndex per node of a point source; answers as one index over all their points
/// would (the nearest of the nodes' picks; on equal distances the node added first).
class PickSet {
  public:
    /// Adds a node's index; `level` is the node's depth in its source's tree (0 the root),
    /// given back in the hits picked from it, -1 when the source has no levels.
    void add(std::shared_ptr<const PickIndex> index, int level = -1);
    /// Points over all the indexes.
    std::size_t size() const { return size_; }
    std::size_t nodes() const { return indexes_.size(); }
    /// The pick over every node, `node` and `level` set in the hit. Never throws.
    std::optional<PickHit> pick(const glm::dvec3& origin, const glm::dvec3& direction,
                                const PickOptions& options = {}) const;
    std::optional<double> nearestTargetDistance(const glm::dvec3& p) const;
    bool hasTargets() const;
    /// The centre of the bounds of every node's points labelled target (local frame); none
    /// without target points.
    std::optional<glm::dvec3> targetCentre() const;

  private:
    std::vector<std::shared_ptr<const PickIndex>> indexes_;
    std::vector<int> levels_;  // one per index
    std::size_t size_ = 0;
};

}  // namespace viewer
