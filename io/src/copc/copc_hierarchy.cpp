// io/src/copc/copc_hierarchy.cpp: see copc_hierarchy.hpp.
#include "copc_hierarchy.hpp"

#include <core/error.hpp>

#include <algorithm>
#include <cstring>
#include <map>

namespace io::detail {

namespace {

// The root of the page that holds a node of this key: its ancestor at the page's top level.
CopcKey pageRoot(const CopcKey& k) {
    const int top = (k.level / kLevelsPerPage) * kLevelsPerPage;
    const int up = k.level - top;
    return {top, k.x >> up, k.y >> up, k.z >> up};
}

// The page above a page root of level >= kLevelsPerPage.
CopcKey parentPage(const CopcKey& root) {
    const CopcKey parent{root.level - 1, root.x >> 1, root.y >> 1, root.z >> 1};
    return pageRoot(parent);
}

template <typename T>
void put(std::string& s, T v) {
    char b[sizeof v];
    std::memcpy(b, &v, sizeof v);  // little-endian hosts, as COPC is
    s.append(b, sizeof v);
}

void putEntry(std::string& s, const CopcKey& k, std::uint64_t offset, std::int32_t size, std::int32_t count) {
    put(s, k.level);
    put(s, k.x);
    put(s, k.y);
    put(s, k.z);
    put(s, offset);
    put(s, size);
    put(s, count);
}

struct Page {
    std::vector<CopcNode> entries;
    std::vector<CopcKey> children;  // child pages' roots
    std::uint64_t offset = 0;
    std::uint64_t size() const { return (entries.size() + children.size()) * kHierarchyEntryBytes; }
};

}  // namespace

HierarchyPages encodeHierarchy(std::vector<CopcNode> nodes, std::uint64_t at) {
    std::map<CopcKey, Page> pages;  // key order: level first, the root page first
    pages[CopcKey{}];
    for (const CopcNode& n : nodes) pages[pageRoot(n.key)].entries.push_back(n);
    for (auto& [root, page] : pages) {
        std::sort(page.entries.begin(), page.entries.end(),
                  [](const CopcNode& a, const CopcNode& b) { return a.key < b.key; });
        if (root.level > 0) {
            const auto parent = pages.find(parentPage(root));
            if (parent == pages.end()) throw core::Error("COPC hierarchy: a node without its ancestors");
            parent->second.children.push_back(root);
        }
    }
    HierarchyPages out;
    std::uint64_t next = at;
    for (auto& [root, page] : pages) {
        page.offset = next;
        next += page.size();
    }
    out.root_size = pages.begin()->second.size();
    out.bytes.reserve(std::size_t(next - at));
    for (const auto& [root, page] : pages) {
        for (const CopcNode& n : page.entries) putEntry(out.bytes, n.key, n.offset, n.byte_size, n.point_count);
        for (const CopcKey& c : page.children) {
            const Page& child = pages.at(c);
            putEntry(out.bytes, c, child.offset, std::int32_t(child.size()), -1);
        }
    }
    return out;
}

}  // namespace io::detail
