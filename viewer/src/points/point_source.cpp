// viewer/src/points/point_source.cpp: the walks over a point source's nodes.
#include <viewer/point_source.hpp>

#include <map>

namespace viewer {

namespace {

void collect(PointNode* node, std::vector<PointNode*>& out) {
    out.push_back(node);
    for (PointNode* child : node->children()) collect(child, out);
}

void collectLevels(const PointNode* node, int level, std::map<const PointNode*, int>& out) {
    out.emplace(node, level);
    for (const PointNode* child : node->children()) collectLevels(child, level + 1, out);
}

}  // namespace

std::vector<PointNode*> allNodes(const PointSource& source) {
    std::vector<PointNode*> out;
    for (PointNode* root : source.roots()) collect(root, out);
    return out;
}

std::map<const PointNode*, int> nodeLevels(const PointSource& source) {
    std::map<const PointNode*, int> out;
    for (const PointNode* root : source.roots()) collectLevels(root, 0, out);
    return out;
}

}  // namespace viewer
