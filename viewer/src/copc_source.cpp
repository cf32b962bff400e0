// viewer/src/copc_source.cpp: a COPC file read node by node into a bounded RAM cache
// (copc_source.hpp): the tree from the hierarchy, one decoding worker, LRU eviction.
#include <viewer/copc_source.hpp>
#include <viewer/lod.hpp>
#include <viewer/node_selection.hpp>

#include <core/error.hpp>
#include <io/copc.hpp>
#include <platform/safe_file.hpp>

#include <algorithm>
#include <condition_variable>
#include <deque>
#include <exception>
#include <map>
#include <mutex>
#include <thread>
#include <utility>

namespace viewer {

namespace {

/// Decoded nodes waiting for poll() at most: with the one being decoded, the memory held
/// outside the cache is a few nodes, whatever the frame rate.
constexpr std::size_t kMaxWaiting = 4;

std::size_t residentBytes(const NodePoints& p) {
    return sizeof(NodePoints) + p.points.capacity() * sizeof(core::CloudPoint) + p.cells.capacity() * sizeof(LodCell);
}

}  // namespace

/// One key of the octree (named, not in an anonymous namespace: CopcSource::Impl holds it).
class CopcTreeNode final : public PointNode {
  public:
    CopcTreeNode(CopcSource::Impl* owner, const io::CopcKey& key, const core::Bounds& bounds, std::size_t count)
        : owner_(owner), key_(key), bounds_(bounds), count_(count) {}
    const core::Bounds& bounds() const override { return bounds_; }
    /// 0 once the node turned out unreadable: the selection walks through it.
    std::size_t pointCount() const override { return failed ? 0 : count_; }
    std::span<PointNode* const> children() const override { return children_; }
    void request() override;
    void evict() override;
    std::shared_ptr<const NodePoints> points() const override { return points_; }

    CopcSource::Impl* owner_;
    io::CopcKey key_;
    core::Bounds bounds_;
    std::size_t count_ = 0;
    std::vector<PointNode*> children_;
    std::shared_ptr<const NodePoints> points_;
    std::size_t bytes = 0;  // while resident
    long last_wanted = -1;  // the selection round that last wanted it (LRU)
    bool queued = false;    // queued, being decoded or not yet polled (owner's mutex)
    bool failed = false;    // its chunk did not decode
};

struct CopcSource::Impl {
    std::unique_ptr<io::CopcReader> reader;
    std::string file;
    CopcSourceOptions options;
    glm::dvec3 origin{0.0};
    core::CloudFields fields;
    std::vector<std::unique_ptr<CopcTreeNode>> nodes;
    std::vector<PointNode*> roots;
    std::size_t total_points = 0;
    // Frame thread only.
    long round = 0;                  // select() calls
    std::vector<PointNode*> wanted;  // by the last selection, most important first
    SourceStats stats;
    bool settled = false;
    bool fields_known = false;  // fields: from the first decoded node
    // Shared with the worker.
    struct Done {
        CopcTreeNode* node = nullptr;
        std::shared_ptr<NodePoints> points;  // null: failed
        std::string error;
        core::CloudFields fields;
    };
    mutable std::mutex mutex;
    std::condition_variable wake;
    std::deque<CopcTreeNode*> queue;
    std::deque<Done> done;
    bool busy = false, stop = false;
    std::size_t points_arrived = 0;
    std::thread worker;

    void enqueue(CopcTreeNode* n) {
        if (n->resident() || n->failed) return;
        {
            std::lock_guard lock(mutex);
            if (n->queued) return;
            n->queued = true;
            queue.push_back(n);
        }
        wake.notify_one();
    }

    void drop(CopcTreeNode* n) {
        if (!n->points_) return;
        n->points_.reset();
        stats.resident_bytes -= n->bytes;
        n->bytes = 0;
        --stats.nodes_resident;
        ++stats.nodes_evicted;
    }

    void work() {
        std::unique_lock lock(mutex);
        while (true) {
            wake.wait(lock, [&] { return stop || (!queue.empty() && done.size() < kMaxWaiting); });
            if (stop) return;
            CopcTreeNode* n = queue.front();
            queue.pop_front();  // queued stays set until poll() takes the result
            busy = true;
            const io::CopcKey key = n->key_;
            lock.unlock();
            Done d;
            d.node = n;
            try {
                core::PointCloud cloud = reader->readNode(key);
                d.fields = cloud.fields;
                auto points = std::make_shared<NodePoints>();
                points->points = std::move(cloud.points);
                points->cells = buildLodOrder(points->points);
                points->points.shrink_to_fit();
                points->cells.shrink_to_fit();
                d.points = std::move(points);
            } catch (const std::exception& e) {
                d.error = e.what();
            }
            lock.lock();
            busy = false;
            if (d.points) points_arrived += d.points->points.size();
            done.push_back(std::move(d));
        }
    }

    /// Makes room for `bytes` by evicting the least recently wanted resident nodes the
    /// last selection did not want. False if that is not enough.
    bool makeRoom(std::size_t bytes) {
        if (stats.resident_bytes + bytes <= options.cache_bytes) return true;
        std::vector<CopcTreeNode*> old;
        for (const auto& n : nodes)
            if (n->points_ && n->last_wanted < round) old.push_back(n.get());
        std::sort(old.begin(), old.end(),
                  [](const CopcTreeNode* a, const CopcTreeNode* b) { return a->last_wanted < b->last_wanted; });
        for (CopcTreeNode* n : old) {
            if (stats.resident_bytes + bytes <= options.cache_bytes) break;
            n->evict();
        }
        return stats.resident_bytes + bytes <= options.cache_bytes;
    }
};

void CopcTreeNode::request() { owner_->enqueue(this); }
void CopcTreeNode::evict() { owner_->drop(this); }

CopcSource::CopcSource(const std::filesystem::path& file, const CopcSourceOptions& options)
    : impl_(std::make_unique<Impl>()) {
    Impl& m = *impl_;
    m.options = options;
    m.file = file.string();
    m.reader = std::make_unique<io::CopcReader>(file);
    m.origin = m.reader->origin();  // every node's points come in this frame
    const io::CopcInfo& info = m.reader->info();
    const glm::dvec3 centre(info.center_m[0], info.center_m[1], info.center_m[2]);
    std::map<io::CopcKey, CopcTreeNode*> by_key;
    // A node, and every node above it (a key may sit below keys the hierarchy leaves out).
    auto ensure = [&](auto& self, const io::CopcKey& k) -> CopcTreeNode* {
        if (auto it = by_key.find(k); it != by_key.end()) return it->second;
        const double side_m = 2.0 * info.halfsize_m / double(std::int64_t(1) << k.level);
        core::Bounds b;
        b.lo = centre - glm::dvec3(info.halfsize_m) + side_m * glm::dvec3(k.x, k.y, k.z) - m.origin;
        b.hi = b.lo + glm::dvec3(side_m);
        m.nodes.push_back(std::make_unique<CopcTreeNode>(&m, k, b, 0));
        CopcTreeNode* n = m.nodes.back().get();
        by_key[k] = n;
        if (k.level == 0)
            m.roots.push_back(n);
        else
            self(self, io::CopcKey{k.level - 1, k.x >> 1, k.y >> 1, k.z >> 1})->children_.push_back(n);
        return n;
    };
    for (const io::CopcNode& c : m.reader->nodes()) {
        CopcTreeNode* n = ensure(ensure, c.key);
        n->count_ = std::size_t(c.point_count);
        m.total_points += n->count_;
    }
    if (m.roots.empty()) ensure(ensure, io::CopcKey{});
    m.stats.kind = "copc";
    m.stats.nodes = m.nodes.size();
    m.stats.cache_bytes = options.cache_bytes;
    // The tree as held: the nodes, their child lists, the root list and the reader's
    // hierarchy entries.
    m.stats.hierarchy_bytes = m.nodes.capacity() * sizeof(std::unique_ptr<CopcTreeNode>) +
                              m.roots.capacity() * sizeof(PointNode*) +
                              m.reader->nodes().capacity() * sizeof(io::CopcNode);
    for (const auto& n : m.nodes)
        m.stats.hierarchy_bytes += sizeof(CopcTreeNode) + n->children_.capacity() * sizeof(PointNode*);
    m.worker = std::thread([&m] { m.work(); });
}

CopcSource::~CopcSource() {
    {
        std::lock_guard lock(impl_->mutex);
        impl_->stop = true;
    }
    impl_->wake.notify_all();
    impl_->worker.join();
}

void CopcSource::select(const SourceView& view) {
    Impl& m = *impl_;
    ++m.round;
    const NodeSelection sel = selectNodes(m.roots, view.frusta, view.eye_local,
                                          SelectionBudget{view.point_budget, m.options.cache_bytes, view.gpu_bytes});
    m.stats.wanted_points = sel.points;
    m.wanted = sel.wanted;
    {
        // The queue follows the latest choice, most important first; what it no longer
        // wants is not decoded (a node being decoded or waiting for poll() stays so).
        std::lock_guard lock(m.mutex);
        for (CopcTreeNode* n : m.queue) n->queued = false;
        m.queue.clear();
        for (PointNode* p : sel.wanted) {
            auto* n = static_cast<CopcTreeNode*>(p);
            n->last_wanted = m.round;
            if (!n->resident() && !n->failed && !n->queued) {
                n->queued = true;
                m.queue.push_back(n);
            }
        }
    }
    m.wake.notify_one();
}

std::size_t CopcSource::poll() {
    Impl& m = *impl_;
    std::deque<Impl::Done> arrived;
    bool idle = false;
    {
        std::lock_guard lock(m.mutex);
        arrived.swap(m.done);
        for (Impl::Done& d : arrived) d.node->queued = false;
        idle = m.queue.empty() && !m.busy;
    }
    if (!arrived.empty()) m.wake.notify_one();
    std::size_t added = 0;
    for (Impl::Done& d : arrived) {
        CopcTreeNode* n = d.node;
        if (!d.points) {
            n->failed = true;
            ++m.stats.nodes_failed;
            if (!m.options.quiet)
                platform::printMessage("warning", "view: " + d.error + " (node skipped, the rest is drawn)");
            continue;
        }
        if (!m.fields_known) {  // the file's fields, as the first decoded node shows them
            m.fields = d.fields;
            m.fields_known = true;
        }
        if (n->points_) continue;  // decoded twice (asked again meanwhile): keep the first
        const std::size_t bytes = residentBytes(*d.points);
        // A node the latest selection no longer wants takes only free room.
        if (n->last_wanted < m.round ? m.stats.resident_bytes + bytes > m.options.cache_bytes : !m.makeRoom(bytes))
            continue;
        n->points_ = std::move(d.points);
        n->bytes = bytes;
        m.stats.resident_bytes += bytes;
        m.stats.resident_bytes_peak = std::max(m.stats.resident_bytes_peak, m.stats.resident_bytes);
        ++m.stats.nodes_resident;
        ++m.stats.nodes_loaded;
        ++added;
    }
    if (!m.settled && m.round > 0 && idle && arrived.empty()) m.settled = true;
    return added;
}

std::span<PointNode* const> CopcSource::roots() const { return impl_->roots; }
glm::dvec3 CopcSource::origin() const { return impl_->origin; }
core::CloudFields CopcSource::fields() const { return impl_->fields; }
bool CopcSource::finished() const { return impl_->settled; }

std::size_t CopcSource::pointsArrived() const {
    std::lock_guard lock(impl_->mutex);
    return impl_->points_arrived;
}

std::optional<SourceStats> CopcSource::stats() const { return impl_->stats; }
std::span<PointNode* const> CopcSource::wanted() const { return impl_->wanted; }
std::size_t CopcSource::nodeCount() const { return impl_->nodes.size(); }
std::size_t CopcSource::totalPoints() const { return impl_->total_points; }

}  // namespace viewer
