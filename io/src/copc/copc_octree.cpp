// io/src/copc/copc_octree.cpp: see copc_octree.hpp. The tree's shape is decided top-down
// by counts, its samples bottom-up: a node samples only once its children are final. The
// first few levels are split on the caller's thread; the subtrees below them are built on
// the worker threads, then the top levels sample. Each node depends on its own subtree
// only, so the result is the same whatever the threads.
#include "copc_octree.hpp"

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <exception>
#include <iterator>
#include <limits>
#include <memory>
#include <mutex>
#include <thread>

namespace io::detail {

namespace {

struct TreeNode {
    CopcKey key;
    std::vector<std::uint32_t> points;
    std::vector<std::uint32_t> pending;  // a subtree left for a worker
    std::array<std::unique_ptr<TreeNode>, 8> child;
};

class Builder {
  public:
    Builder(std::span<const std::array<std::int32_t, 3>> xyz, const OctreeCube& cube, std::uint32_t cap)
        : xyz_(xyz), cube_(cube), cap_(cap) {}

    // Splits down to `stop_level` (-1: no stop), leaving subtrees there in `tasks`; samples
    // the nodes it completed.
    void split(TreeNode& node, std::vector<std::uint32_t> idx, int stop_level, std::vector<TreeNode*>* tasks,
               Marks& marks) const {
        const int level = node.key.level;
        if (idx.size() <= cap_ || level >= cube_.bits) {
            node.points = std::move(idx);
            return;
        }
        if (level == stop_level) {
            node.pending = std::move(idx);
            tasks->push_back(&node);
            return;
        }
        const int shift = cube_.bits - level - 1;
        std::array<std::vector<std::uint32_t>, 8> parts;
        {
            std::array<std::size_t, 8> count{};
            for (std::uint32_t i : idx) ++count[octant(i, shift)];
            for (std::size_t o = 0; o < 8; ++o) parts[o].reserve(count[o]);
            for (std::uint32_t i : idx) parts[octant(i, shift)].push_back(i);
            std::vector<std::uint32_t>().swap(idx);
        }
        for (std::size_t o = 0; o < 8; ++o) {
            if (parts[o].empty()) continue;
            auto c = std::make_unique<TreeNode>();
            c->key = {level + 1, 2 * node.key.x + int(o & 1u), 2 * node.key.y + int((o >> 1) & 1u),
                      2 * node.key.z + int((o >> 2) & 1u)};
            split(*c, std::move(parts[o]), stop_level, tasks, marks);
            node.child[o] = std::move(c);
        }
        if (stop_level < 0) sample(node, marks);
    }

    // Samples the nodes above `level` once the subtrees at `level` are built.
    void sampleAbove(TreeNode& node, int level, Marks& marks) const {
        if (node.key.level >= level) return;
        bool inner = false;
        for (auto& c : node.child)
            if (c) {
                sampleAbove(*c, level, marks);
                inner = true;
            }
        if (inner) sample(node, marks);
    }

  private:
    std::size_t octant(std::uint32_t i, int shift) const {
        std::size_t o = 0;
        for (std::size_t k = 0; k < 3; ++k)
            o |= std::size_t(((std::int64_t(xyz_[i][k]) - cube_.corner[k]) >> shift) & 1) << k;
        return o;
    }

    void sample(TreeNode& node, Marks& marks) const {
        std::vector<std::vector<std::uint32_t>*> children;
        for (auto& c : node.child)
            if (c) children.push_back(&c->points);
        node.points = gridSample(xyz_, cube_, node.key.level, children, cap_, marks);
    }

    std::span<const std::array<std::int32_t, 3>> xyz_;
    OctreeCube cube_;
    std::size_t cap_;
};

void flatten(TreeNode& node, std::vector<OctreeNode>& out) {
    out.push_back({node.key, std::move(node.points)});
    for (auto& c : node.child)
        if (c) flatten(*c, out);
}

}  // namespace

void Marks::reset() {
    if (cell.empty()) cell.assign(std::size_t(1) << (3 * kGridBits), 0u);
    if (++generation == 0) {
        std::fill(cell.begin(), cell.end(), 0u);
        generation = 1;
    }
}

std::vector<std::uint32_t> gridSample(std::span<const std::array<std::int32_t, 3>> xyz, const OctreeCube& cube,
                                      int level, std::span<std::vector<std::uint32_t>* const> children, std::size_t cap,
                                      Marks& marks) {
    // The children's points in input order: each child's are ascending already, so they
    // are merged (a child's points are in no other child).
    std::vector<std::uint32_t> candidates;
    {
        std::size_t total = 0;
        for (const std::vector<std::uint32_t>* c : children) total += c->size();
        candidates.reserve(total);
        std::vector<std::size_t> head(children.size(), 0);
        for (;;) {
            std::size_t best = children.size();
            std::uint32_t least = 0;
            for (std::size_t c = 0; c < children.size(); ++c)
                if (head[c] < children[c]->size() && (best == children.size() || (*children[c])[head[c]] < least)) {
                    best = c;
                    least = (*children[c])[head[c]];
                }
            if (best == children.size()) break;
            // The run of the best child below every other child's next point goes at once.
            std::uint32_t bound = std::numeric_limits<std::uint32_t>::max();
            for (std::size_t c = 0; c < children.size(); ++c)
                if (c != best && head[c] < children[c]->size()) bound = std::min(bound, (*children[c])[head[c]]);
            const std::vector<std::uint32_t>& run = *children[best];
            std::size_t end = head[best];
            while (end < run.size() && run[end] < bound) ++end;
            candidates.insert(candidates.end(), run.begin() + std::ptrdiff_t(head[best]),
                              run.begin() + std::ptrdiff_t(end));
            head[best] = end;
        }
    }
    const int node_bits = cube.bits - level;
    std::vector<std::uint32_t> chosen;
    for (int s = std::max(0, node_bits - kGridBits); s <= node_bits; ++s) {
        marks.reset();
        chosen.clear();
        constexpr std::int64_t kMask = (std::int64_t(1) << kGridBits) - 1;
        for (std::uint32_t i : candidates) {
            std::size_t cell = 0;
            for (std::size_t k = 0; k < 3; ++k)
                cell |= std::size_t(((std::int64_t(xyz[i][k]) - cube.corner[k]) >> s) & kMask) << (kGridBits * k);
            if (marks.cell[cell] == marks.generation) continue;
            marks.cell[cell] = marks.generation;
            chosen.push_back(i);
        }
        if (chosen.size() <= cap) break;
    }
    for (std::vector<std::uint32_t>* c : children) {
        std::vector<std::uint32_t> kept;
        kept.reserve(c->size());
        std::set_difference(c->begin(), c->end(), chosen.begin(), chosen.end(), std::back_inserter(kept));
        *c = std::move(kept);
    }
    return chosen;
}

OctreeCube enclosingCube(const std::array<std::int32_t, 3>& min, const std::array<std::int32_t, 3>& max) {
    std::int64_t extent = 0;
    for (std::size_t k = 0; k < 3; ++k) extent = std::max(extent, std::int64_t(max[k]) - std::int64_t(min[k]));
    OctreeCube cube;
    while ((std::int64_t(1) << cube.bits) <= extent) ++cube.bits;
    const std::int64_t edge = std::int64_t(1) << cube.bits;
    for (std::size_t k = 0; k < 3; ++k) {
        const std::int64_t width = std::int64_t(max[k]) - std::int64_t(min[k]);
        cube.corner[k] = std::int64_t(min[k]) - (edge - 1 - width) / 2;
    }
    return cube;
}

void parallelFor(std::size_t n, int threads, const std::function<void(std::size_t, std::size_t)>& fn) {
    std::vector<std::exception_ptr> errors(n);
    std::atomic<std::size_t> next{0};
    const auto work = [&](std::size_t worker) {
        for (std::size_t i; (i = next.fetch_add(1)) < n;) {
            try {
                fn(i, worker);
            } catch (...) {
                errors[i] = std::current_exception();
            }
        }
    };
    std::vector<std::thread> pool;
    const std::size_t helpers = std::min<std::size_t>(std::size_t(std::max(threads, 0)), n > 0 ? n - 1 : 0);
    for (std::size_t t = 0; t < helpers; ++t) pool.emplace_back(work, t + 1);
    work(0);
    for (std::thread& t : pool) t.join();
    for (const std::exception_ptr& e : errors)
        if (e) std::rethrow_exception(e);
}

void orderedParallel(std::size_t n, int threads, std::size_t window, const std::function<void(std::size_t)>& work,
                     const std::function<void(std::size_t)>& emit,
                     const std::function<std::size_t(std::size_t, bool)>& weight) {
    window = std::max<std::size_t>(window, 1);
    std::mutex m;
    std::condition_variable changed;
    std::size_t next = 0, emitted = 0, running = 0;
    std::size_t held = 0;                // the weight of the items begun and not yet emitted
    std::vector<std::size_t> weighs(n);  // each one's part of it
    std::vector<char> done(n, 0);
    std::vector<std::exception_ptr> errors(n);
    std::exception_ptr emit_error;
    bool stop = false;
    const auto weightOf = [&](std::size_t i, bool worked) { return weight ? weight(i, worked) : std::size_t(1); };
    // An item begins when the window has room for it, or when it would be alone in it.
    const auto canBegin = [&] {
        return !stop && next < n && (next == emitted || held + weightOf(next, false) <= window);
    };
    // Runs item i with the lock released; returns with it held.
    const auto run = [&](std::unique_lock<std::mutex>& lock, std::size_t i) {
        ++running;
        weighs[i] = weightOf(i, false);
        held += weighs[i];
        lock.unlock();
        std::size_t worked = 0;
        try {
            work(i);
            worked = weightOf(i, true);
        } catch (...) {
            errors[i] = std::current_exception();
        }
        lock.lock();
        held = held - weighs[i] + worked;
        weighs[i] = worked;
        --running;
        done[i] = 1;
        if (errors[i]) stop = true;
        changed.notify_all();
    };
    const auto helper = [&] {
        std::unique_lock<std::mutex> lock(m);
        for (;;) {
            changed.wait(lock, [&] { return canBegin() || stop || next >= n; });
            if (!canBegin()) return;
            run(lock, next++);
        }
    };
    std::vector<std::thread> pool;
    const std::size_t helpers = std::min<std::size_t>(std::size_t(std::max(threads, 0)), n > 0 ? n - 1 : 0);
    for (std::size_t t = 0; t < helpers; ++t) pool.emplace_back(helper);
    {
        std::unique_lock<std::mutex> lock(m);
        while (emitted < n) {
            if (done[emitted] && !errors[emitted] && !stop) {
                const std::size_t i = emitted;
                lock.unlock();
                try {
                    emit(i);
                } catch (...) {
                    emit_error = std::current_exception();
                }
                lock.lock();
                if (emit_error) {
                    stop = true;
                    changed.notify_all();
                    break;
                }
                held -= weighs[i];
                ++emitted;
                changed.notify_all();
            } else if (canBegin()) {
                run(lock, next++);
            } else if (stop) {
                break;
            } else {
                changed.wait(lock);
            }
        }
        stop = true;
        changed.notify_all();
        changed.wait(lock, [&] { return running == 0; });
    }
    for (std::thread& t : pool) t.join();
    if (emit_error) std::rethrow_exception(emit_error);
    for (const std::exception_ptr& e : errors)
        if (e) std::rethrow_exception(e);
}

std::vector<OctreeNode> buildOctree(std::span<const std::array<std::int32_t, 3>> xyz, const OctreeCube& cube,
                                    std::uint32_t max_node_points, int threads, std::vector<Marks>* marks_kept) {
    const Builder builder(xyz, cube, std::max<std::uint32_t>(max_node_points, 1));
    TreeNode root;
    std::vector<std::uint32_t> all(xyz.size());
    for (std::size_t i = 0; i < all.size(); ++i) all[i] = std::uint32_t(i);
    std::vector<Marks> own_marks;
    std::vector<Marks>& marks = marks_kept ? *marks_kept : own_marks;
    marks.resize(std::max<std::size_t>(marks.size(), std::size_t(std::max(threads, 0)) + 1));
    // Enough subtrees for the workers to share: 8^stop >= 4 (threads + 1).
    int stop = -1;
    if (threads > 0) {
        stop = 1;
        while (stop < 3 && (std::size_t(1) << (3 * stop)) < 4 * std::size_t(threads + 1)) ++stop;
    }
    std::vector<TreeNode*> tasks;
    builder.split(root, std::move(all), stop, &tasks, marks[0]);
    if (stop >= 0) {
        parallelFor(tasks.size(), threads, [&](std::size_t i, std::size_t worker) {
            TreeNode& t = *tasks[i];
            builder.split(t, std::move(t.pending), -1, nullptr, marks[worker]);
        });
        builder.sampleAbove(root, stop, marks[0]);
    }
    std::vector<OctreeNode> out;
    flatten(root, out);
    return out;
}

}  // namespace io::detail
