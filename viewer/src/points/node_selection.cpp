// viewer/src/points/node_selection.cpp: the per-frame node choice of node_selection.hpp.
#include <viewer/lod.hpp>
#include <viewer/node_selection.hpp>

#include <render/point_chunks.hpp>

#include <algorithm>
#include <cmath>
#include <queue>

namespace viewer {

std::size_t nodeBytes(std::size_t point_count) {
    // buildLodOrder's grid: side = max(1, ceil(sqrt(n / cell_points))), at most side^2 cells.
    const LodOptions lod;
    const auto side =
        static_cast<std::size_t>(std::max(1.0, std::ceil(std::sqrt(double(point_count) / double(lod.cell_points)))));
    return sizeof(NodePoints) + point_count * sizeof(core::CloudPoint) + side * side * sizeof(LodCell);
}

std::size_t gpuBytes(std::size_t point_count) { return point_count * sizeof(render::GpuPoint); }

NodeSelection selectNodes(std::span<PointNode* const> roots, std::span<const render::Frustum> frusta,
                          const glm::dvec3& eye_local, const SelectionBudget& budget, const LodFocus& focus) {
    NodeSelection out;
    const auto seen = [&](const PointNode* n) {
        if (n->bounds().empty()) return false;
        if (frusta.empty()) return true;
        return std::any_of(frusta.begin(), frusta.end(),
                           [&](const render::Frustum& f) { return f.intersects(n->bounds()); });
    };
    // Focused nodes first (a focused node's parent touches the focus too, so the focus's
    // subtree is taken whole before any other node), then by importance.
    struct Item {
        bool focused = false;
        double importance = 0.0;
        PointNode* node = nullptr;
    };
    const auto less = [](const Item& a, const Item& b) {
        return a.focused != b.focused ? b.focused : a.importance < b.importance;
    };
    std::priority_queue<Item, std::vector<Item>, decltype(less)> queue(less);
    const auto push = [&](PointNode* n) {
        if (seen(n)) queue.push({focus.touches(n->bounds()), screenImportance(n->bounds(), eye_local), n});
    };
    for (PointNode* r : roots) push(r);
    while (!queue.empty()) {
        const Item item = queue.top();
        PointNode* n = item.node;
        queue.pop();
        const std::size_t count = n->pointCount();
        const std::size_t bytes = count ? nodeBytes(count) : 0;
        const std::size_t gpu = gpuBytes(count);
        if ((budget.points && !item.focused && out.points + count > budget.points) ||
            (budget.bytes && out.bytes + bytes > budget.bytes) ||
            (budget.gpu_bytes && out.gpu_bytes + gpu > budget.gpu_bytes))
            continue;  // does not fit: neither it nor its subtree (its children need it first)
        if (n->unexplored()) out.unexplored.push_back(n);
        if (count) {
            out.wanted.push_back(n);
            out.points += count;
            if (item.focused) out.focus_points += count;
            out.bytes += bytes;
            out.gpu_bytes += gpu;
        }
        for (PointNode* c : n->children()) push(c);
    }
    return out;
}

}  // namespace viewer
