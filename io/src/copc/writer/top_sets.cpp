// io/src/copc/writer/top_sets.cpp: the upper nodes' sets and their bottom-up sampling
// (top_sets.hpp).
#include "top_sets.hpp"

#include <algorithm>

namespace io::detail::copc_writer {

TopSets::TopSets(const WriterSetup& setup) : setup_(setup), file_(setup.scratchFile()) {}

std::uint64_t TopSets::append(std::span<const Lifted> run) {
    const std::uint64_t at = end_;
    file_.append(run.data(), run.size_bytes());
    end_ += run.size_bytes();
    return at;
}

// Streams the sets of the tops `which` (each ascending by input index) merged into one
// ascending sequence, a buffer of records per set, and hands each record to `fn` with the
// position of its set; stops early when `fn` returns false.
template <typename Fn>
void TopSets::merge(const std::vector<Top>& tops, std::span<const int> which, Fn fn) {
    constexpr std::size_t kBuffer = 4096;
    struct Cursor {
        std::uint64_t at = 0, left = 0;
        std::vector<Lifted> buf;
        std::size_t next = 0;
    };
    std::vector<Cursor> cur(which.size());
    file_.flush();
    const auto fill = [&](Cursor& c) {
        const std::size_t n = std::size_t(std::min<std::uint64_t>(kBuffer, c.left));
        c.buf.resize(n);
        file_.readAt(c.buf.data(), n * sizeof(Lifted), c.at);
        c.at += n * sizeof(Lifted);
        c.left -= n;
        c.next = 0;
    };
    for (std::size_t i = 0; i < which.size(); ++i) {
        const Top& t = tops[std::size_t(which[i])];
        cur[i].at = t.set_at;
        cur[i].left = t.set_n;
        fill(cur[i]);
    }
    for (;;) {
        std::size_t best = cur.size();
        for (std::size_t i = 0; i < cur.size(); ++i) {
            if (cur[i].next == cur[i].buf.size()) continue;
            if (best == cur.size() ||
                cur[i].buf[cur[i].next].spilled.index < cur[best].buf[cur[best].next].spilled.index)
                best = i;
        }
        if (best == cur.size()) return;
        Cursor& c = cur[best];
        if (!fn(c.buf[c.next], best)) return;
        if (++c.next == c.buf.size() && c.left > 0) fill(c);
    }
}

void TopSets::sample(PartTree& tree, const OctreeCube& cube, int t, Marks& marks) {
    std::vector<Top>& tops = tree.tops;
    if (tops[std::size_t(t)].bucket >= 0) return;
    std::vector<int> children;
    for (int c : tops[std::size_t(t)].child)
        if (c >= 0) {
            sample(tree, cube, c, marks);
            children.push_back(c);
        }
    const CopcKey key = tops[std::size_t(t)].key;
    const int node_bits = cube.bits - key.level;
    constexpr std::int64_t kMask = (std::int64_t(1) << kGridBits) - 1;
    std::vector<std::uint64_t> chosen;  // input indices, ascending
    for (int shift = std::max(0, node_bits - kGridBits); shift <= node_bits; ++shift) {
        marks.reset();
        chosen.clear();
        merge(tops, children, [&](const Lifted& p, std::size_t) {
            std::size_t cell = 0;
            for (std::size_t k = 0; k < 3; ++k)
                cell |= std::size_t(((std::int64_t(p.xyz[k]) - cube.corner[k]) >> shift) & kMask) << (kGridBits * k);
            if (marks.cell[cell] == marks.generation) return true;
            marks.cell[cell] = marks.generation;
            chosen.push_back(p.spilled.index);
            return chosen.size() <= setup_.cap;  // past the cap this grid is too fine
        });
        if (chosen.size() <= setup_.cap) break;
    }
    // Each child's set without the chosen points, then the node's own set.
    std::vector<Lifted> mine;
    mine.reserve(chosen.size());
    std::vector<Lifted> rest;
    for (int c : children) {
        std::uint64_t kept = 0;
        rest.clear();
        const std::uint64_t at = end_;
        const int one[1] = {c};
        merge(tops, one, [&](const Lifted& p, std::size_t) {
            if (std::binary_search(chosen.begin(), chosen.end(), p.spilled.index)) {
                mine.push_back(p);
            } else {
                rest.push_back(p);
                ++kept;
                if (rest.size() == 4096) {
                    append(rest);
                    rest.clear();
                }
            }
            return true;
        });
        append(rest);
        tops[std::size_t(c)].set_at = at;
        tops[std::size_t(c)].set_n = kept;
    }
    std::sort(mine.begin(), mine.end(),
              [](const Lifted& a, const Lifted& b) { return a.spilled.index < b.spilled.index; });
    Top& top = tops[std::size_t(t)];
    top.set_n = mine.size();
    top.set_at = append(mine);
}

}  // namespace io::detail::copc_writer
