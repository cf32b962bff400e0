// tests/viewer/points/node_selection_test.cpp: the per-frame node choice over a hand-built tree
// (no GL): the budget is never exceeded, parents come before their children, nearer and
// larger nodes before farther ones, nodes outside every frustum are left out, and the
// traversal never looks below a node it did not take.
#include <viewer/node_selection.hpp>

#include <render/orbit_camera.hpp>

#include <glm/gtc/matrix_transform.hpp>

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

using namespace viewer;

namespace {

class TestNode final : public PointNode {
  public:
    TestNode(const glm::dvec3& lo, double side_m, std::size_t count) : count_(count) {
        bounds_.lo = lo;
        bounds_.hi = lo + glm::dvec3(side_m);
    }
    const core::Bounds& bounds() const override { return bounds_; }
    std::size_t pointCount() const override { return count_; }
    std::span<PointNode* const> children() const override {
        ++children_calls;
        return children_;
    }
    void request() override {}
    void evict() override { points_.reset(); }
    std::shared_ptr<const NodePoints> points() const override { return points_; }

    core::Bounds bounds_;
    std::size_t count_;
    std::vector<PointNode*> children_;
    std::shared_ptr<const NodePoints> points_;
    mutable int children_calls = 0;  // how often the traversal asked for the children
};

/// An octree of `levels` levels over the cube [0, 64)^3, `per_node` points in each node.
struct Tree {
    std::vector<std::unique_ptr<TestNode>> nodes;
    std::vector<PointNode*> roots;
    TestNode* add(const glm::dvec3& lo, double side, int levels, std::size_t per_node) {
        nodes.push_back(std::make_unique<TestNode>(lo, side, per_node));
        TestNode* n = nodes.back().get();
        if (levels > 1)
            for (int i = 0; i < 8; ++i) {
                const glm::dvec3 o(i & 1, (i >> 1) & 1, (i >> 2) & 1);
                n->children_.push_back(add(lo + o * (side / 2), side / 2, levels - 1, per_node));
            }
        return n;
    }
    explicit Tree(int levels, std::size_t per_node = 100) {
        roots.push_back(add(glm::dvec3(0.0), 64.0, levels, per_node));
    }
};

PointNode* parentOf(const Tree& t, const PointNode* child) {
    for (const auto& n : t.nodes)
        for (PointNode* c : n->children_)
            if (c == child) return n.get();
    return nullptr;
}

std::size_t levelOf(const PointNode* n) { return std::size_t(std::lround(std::log2(64.0 / n->bounds().size().x))); }

}  // namespace

TEST_CASE("selectNodes never exceeds the point or byte budget and takes parents first") {
    const Tree tree(4);  // 1 + 8 + 64 + 512 nodes of 100 points
    const glm::dvec3 eye(10.0, 10.0, 80.0);
    for (std::size_t budget : {50u, 100u, 250u, 950u, 5000u, 30000u}) {
        const NodeSelection s = selectNodes(tree.roots, {}, eye, {budget, 0});
        CHECK(s.points <= budget);
        std::size_t sum = 0;
        for (const PointNode* n : s.wanted) sum += n->pointCount();
        CHECK(sum == s.points);
        CHECK(s.wanted.size() == std::min<std::size_t>(budget / 100, 585));
        for (std::size_t i = 0; i < s.wanted.size(); ++i) {
            const PointNode* parent = parentOf(tree, s.wanted[i]);
            if (!parent) continue;
            const auto at = std::find(s.wanted.begin(), s.wanted.end(), parent);
            REQUIRE(at != s.wanted.end());
            CHECK(at < s.wanted.begin() + std::ptrdiff_t(i));
        }
    }
    const std::size_t bytes = 10 * nodeBytes(100) + 7;
    const NodeSelection s = selectNodes(tree.roots, {}, eye, {0, bytes});
    CHECK(s.bytes <= bytes);
    CHECK(s.wanted.size() == 10);
}

TEST_CASE("selectNodes prefers the nodes nearer the eye, coarse to fine") {
    const Tree tree(3);
    const glm::dvec3 eye(4.0, 4.0, 4.0);  // inside the corner child (0, 0, 0) and its first child
    const PointNode* root = tree.roots[0];
    const PointNode* corner = root->children()[0];
    const PointNode* far_child = root->children()[7];  // the level-1 node at (32, 32, 32)
    // 17 nodes: the root, the corner and all its children come before the farthest
    // level-1 node, whose screen size is smaller than theirs.
    const NodeSelection s = selectNodes(tree.roots, {}, eye, {1700, 0});
    REQUIRE(s.wanted.size() == 17);
    CHECK(s.wanted[0] == root);
    CHECK(s.wanted[1] == corner);
    CHECK(s.wanted[2] == corner->children()[0]);  // the eye is inside it
    for (const PointNode* c : corner->children())
        CHECK(std::find(s.wanted.begin(), s.wanted.end(), c) != s.wanted.end());
    CHECK(std::find(s.wanted.begin(), s.wanted.end(), far_child) == s.wanted.end());
    CHECK(std::find(s.wanted.begin(), s.wanted.end(), far_child->children()[7]) == s.wanted.end());
    // With more budget it comes in.
    const NodeSelection more = selectNodes(tree.roots, {}, eye, {3000, 0});
    CHECK(std::find(more.wanted.begin(), more.wanted.end(), far_child) != more.wanted.end());
    // With less budget the far level-1 node gives way to the near level-2 ones.
    const NodeSelection less = selectNodes(tree.roots, {}, eye, {1200, 0});
    REQUIRE(less.wanted.size() == 12);
    CHECK(std::find(less.wanted.begin(), less.wanted.end(), far_child) == less.wanted.end());
    CHECK(std::count_if(less.wanted.begin(), less.wanted.end(), [](const PointNode* n) { return levelOf(n) == 2; }) ==
          7);
}

TEST_CASE("selectNodes leaves out nodes outside every frustum and walks through empty nodes") {
    Tree tree(3);
    tree.nodes[0]->count_ = 0;  // the root has no points of its own
    // Looking down -x from x = 200 at the cube's half with y < 32 only (a narrow frustum).
    const glm::dmat4 view =
        glm::lookAt(glm::dvec3(200.0, 16.0, 32.0), glm::dvec3(0.0, 16.0, 32.0), glm::dvec3(0, 0, 1));
    const glm::dmat4 proj = glm::perspective(glm::radians(6.0), 1.0, 0.1, 1000.0);
    const std::vector<render::Frustum> frusta{render::Frustum::fromMatrix(proj * view)};
    const NodeSelection s = selectNodes(tree.roots, frusta, glm::dvec3(200.0, 16.0, 32.0), {0, 0});
    REQUIRE(!s.wanted.empty());
    for (const PointNode* n : s.wanted) {
        CHECK(n->pointCount() > 0);
        CHECK(n->bounds().lo.y < 32.0);  // nothing wholly on the far side of y = 32
    }
    const std::size_t all = selectNodes(tree.roots, {}, glm::dvec3(200.0, 16.0, 32.0), {0, 0}).wanted.size();
    CHECK(all == 72);  // 8 + 64: every node with points
    CHECK(s.wanted.size() < all);
}

TEST_CASE("selectNodes looks only at the nodes it takes and their children") {
    Tree tree(4);  // 1 + 8 + 64 + 512 nodes
    auto points = std::make_shared<NodePoints>();
    tree.nodes.back()->points_ = points;  // a resident leaf far from what is taken
    // Room for the root and its 8 children only.
    const NodeSelection s = selectNodes(tree.roots, {}, glm::dvec3(1.0), {900, 0});
    CHECK(s.wanted.size() == 9);
    CHECK(s.points == 900);
    std::size_t asked = 0;
    for (const auto& n : tree.nodes) asked += n->children_calls > 0;
    CHECK(asked == 9);  // the root and its children, whose own children were pushed and refused
    CHECK(tree.nodes.back()->children_calls == 0);
}

TEST_CASE("selectNodes keeps the wanted nodes within the GPU arena's bytes") {
    const Tree tree(4);
    const glm::dvec3 eye(10.0, 10.0, 80.0);
    CHECK(gpuBytes(100) == 100 * 20);  // one render::GpuPoint per point
    const std::size_t gpu = 12 * gpuBytes(100) + 19;
    const NodeSelection s = selectNodes(tree.roots, {}, eye, {0, 0, gpu});
    CHECK(s.gpu_bytes <= gpu);
    CHECK(s.gpu_bytes == s.points * 20);
    CHECK(s.wanted.size() == 12);
    // The tightest of the three bounds decides.
    const NodeSelection t = selectNodes(tree.roots, {}, eye, {500, 0, gpu});
    CHECK(t.wanted.size() == 5);
}

TEST_CASE("selectNodes: the nodes touching the focus are taken down to the leaves whatever the budget") {
    const Tree tree(4);  // leaves 8 m wide
    const glm::dvec3 eye(10.0, 10.0, 80.0);
    LodFocus focus;
    focus.spheres.push_back({glm::dvec3(52.0, 52.0, 4.0), 1.0});  // inside one leaf, far from the eye
    const std::size_t budget = 250;
    const NodeSelection plain = selectNodes(tree.roots, {}, eye, {budget, 0});
    const NodeSelection focused = selectNodes(tree.roots, {}, eye, {budget, 0}, focus);
    const auto touching = [&](const NodeSelection& s) {
        return std::count_if(s.wanted.begin(), s.wanted.end(),
                             [&](const PointNode* n) { return focus.touches(n->bounds()); });
    };
    // Without the focus the budget stops at level 1 near the eye; with it the focus's
    // path from the root to its leaf (4 nodes) is all taken, first, and the rest gives way.
    CHECK(touching(plain) < 4);
    CHECK(touching(focused) == 4);
    for (std::size_t i = 0; i < 4; ++i) CHECK(focus.touches(focused.wanted[i]->bounds()));
    CHECK(focused.focus_points == 400);
    CHECK(focused.points <= std::max<std::size_t>(budget, focused.focus_points));
    // Parents still come before their children.
    for (std::size_t i = 0; i < focused.wanted.size(); ++i)
        if (const PointNode* p = parentOf(tree, focused.wanted[i]))
            CHECK(std::find(focused.wanted.begin(), focused.wanted.begin() + std::ptrdiff_t(i), p) !=
                  focused.wanted.begin() + std::ptrdiff_t(i));
    // A budget smaller than the focus: the focus alone is taken.
    const NodeSelection tight = selectNodes(tree.roots, {}, eye, {50, 0}, focus);
    CHECK(tight.points == 400);
    CHECK(tight.wanted.size() == 4);
    // The RAM bound still holds for the focus.
    const NodeSelection bytes = selectNodes(tree.roots, {}, eye, {0, 2 * nodeBytes(100)}, focus);
    CHECK(bytes.wanted.size() == 2);
}
