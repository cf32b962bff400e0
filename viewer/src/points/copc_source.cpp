// viewer/src/points/copc_source.cpp: a COPC file read node by node into a bounded RAM cache
// (copc_source.hpp): the tree from the hierarchy, read page by page, workers for pages
// and nodes, LRU eviction.
#include <viewer/copc_source.hpp>

#include "points/file_colours.hpp"
#include "points/point_attributes.hpp"

#include <viewer/lod.hpp>
#include <viewer/node_selection.hpp>

#include <core/error.hpp>
#include <io/copc.hpp>
#include <platform/safe_file.hpp>

#include <algorithm>
#include <cmath>
#include <condition_variable>
#include <deque>
#include <exception>
#include <mutex>
#include <optional>
#include <set>
#include <span>
#include <thread>
#include <utility>

namespace viewer {

namespace {

/// Decoded nodes waiting for poll() at most: with those being decoded (one per worker),
/// the memory held outside the cache is a few nodes, whatever the frame rate.
constexpr std::size_t kMaxWaiting = 4;

std::size_t residentBytes(const NodePoints& p) {
    return sizeof(NodePoints) + p.points.capacity() * sizeof(core::CloudPoint) + p.cells.capacity() * sizeof(LodCell);
}

/// What reading a hierarchy page holds per 32-byte entry until its nodes join the tree:
/// the page's bytes, the reader's map of the keys seen and the entry lists handed back
/// (each list up to twice its length while it grows), rounded up.
constexpr std::size_t kPageEntryBytes = 256;

/// The deepest level a COPC key may have for a cube of `halfsize_m` whose coordinates step
/// by `scale_m`: the first level whose cells are at most one step wide. A cell that narrow
/// holds one coordinate per axis, so no level below it can separate points.
int resolvedLevels(double halfsize_m, double scale_m) {
    const double cells = 2.0 * halfsize_m / scale_m;
    if (!(cells > 1.0)) return 0;
    return static_cast<int>(std::min(30.0, std::ceil(std::log2(cells))));
}

io::CopcKey parentKey(const io::CopcKey& k) { return {k.level - 1, k.x >> 1, k.y >> 1, k.z >> 1}; }

std::string mib(std::size_t bytes) { return core::shownNumber(double(bytes) / 1048576.0, 4); }

}  // namespace

std::size_t defaultCopcWorkers() { return std::clamp<std::size_t>(std::thread::hardware_concurrency() / 2, 1, 4); }

/// One key of the octree (named, not in an anonymous namespace: CopcSource::Impl holds it).
class CopcTreeNode final : public PointNode {
  public:
    CopcTreeNode(CopcSource::Impl* owner, const io::CopcKey& key, const core::Bounds& bounds)
        : owner_(owner), bounds_(bounds) {
        entry.key = key;
    }
    const core::Bounds& bounds() const override { return bounds_; }
    /// 0 once the node turned out unreadable: the selection walks through it.
    std::size_t pointCount() const override { return failed ? 0 : std::size_t(entry.point_count); }
    std::span<PointNode* const> children() const override { return children_; }
    bool unexplored() const override { return page.bytes > 0 && !page_failed; }
    void request() override;
    void evict() override;
    std::shared_ptr<const NodePoints> points() const override { return points_; }
    const io::CopcKey& key() const { return entry.key; }

    CopcSource::Impl* owner_;
    io::CopcNode entry;  // point_count 0: no points (or not known yet)
    io::CopcPage page;   // bytes > 0 while its hierarchy page is not read
    core::Bounds bounds_;
    std::vector<PointNode*> children_;
    std::shared_ptr<const NodePoints> points_;
    std::size_t bytes = 0;     // while resident
    long last_wanted = -1;     // the selection round that last wanted it (LRU)
    bool queued = false;       // queued, being decoded or not yet polled (owner's mutex)
    bool failed = false;       // its chunk did not decode
    bool page_queued = false;  // its page: queued, being read or not yet polled (owner's mutex)
    bool page_failed = false;  // its page did not read: its subtree stays unknown
};

/// What one node of the tree takes: the node, its slot in the source's list and in its
/// parent's child list (each list up to twice its length while it grows), and the
/// allocator's header.
constexpr std::size_t kTreeNodeBytes = sizeof(CopcTreeNode) + 4 * sizeof(void*) + 16;

struct CopcSource::Impl {
    std::unique_ptr<io::CopcReader> reader;
    std::string file;
    CopcSourceOptions options;
    glm::dvec3 origin{0.0};
    core::CloudFields fields;
    bool from_elsewhere = false;  // with fields: from the first decoded node
    io::CopcInfo info;
    std::vector<std::unique_ptr<CopcTreeNode>> nodes;
    std::vector<PointNode*> roots;
    int max_level = 30;         // keys below it cannot separate points (resolvedLevels)
    std::size_t max_nodes = 0;  // the tree's share of options.hierarchy_bytes
    std::size_t total_points = 0;
    std::size_t pages_wanted = 0;  // unexplored nodes the last selection reached
    // Frame thread only.
    long round = 0;                  // select() calls
    std::vector<PointNode*> wanted;  // by the last selection, most important first
    SourceStats stats;
    bool settled = false;
    bool fields_known = false;  // fields: from the first decoded node
    // Shared with the workers.
    struct Done {
        CopcTreeNode* node = nullptr;
        bool page = false;                   // its hierarchy page, not its points
        std::shared_ptr<NodePoints> points;  // null: failed (a node)
        io::CopcPageEntries entries;         // a page
        std::string error;                   // empty: read
        core::CloudFields fields;
        bool from_elsewhere = false;
    };
    mutable std::mutex mutex;
    std::condition_variable wake;
    /// The intensities' stretch of the class, intensity and return colours (point_attributes.hpp):
    /// the first decoded node's.
    std::optional<IntensityStretch> stretch;
    /// A file from elsewhere's colours at the depth its values read so far show.
    FileColours colours;

    /// A decoded node's points as the viewer draws them (a worker, unlocked): a file from
    /// elsewhere's colours at their depth (file_colours.hpp: the values read so far decide,
    /// as for a streamed file's chunks), and without heights above ground the packed class,
    /// intensity and returns in their place.
    void prepare(core::PointCloud& cloud) {
        const std::size_t stride = cloud.foreign ? cloud.foreign->header.stride() : 0;
        const std::span<const unsigned char> records =
            cloud.foreign ? std::span<const unsigned char>(cloud.foreign->records) : std::span<const unsigned char>();
        std::optional<IntensityStretch> s;
        {
            std::lock_guard lock(mutex);
            if (cloud.foreign && cloud.fields.rgb) colours.recolour(cloud.points, records, stride);
            if (!stretch) stretch = IntensityStretch::of(cloud.points);
            s = stretch;
        }
        if (!cloud.fields.height_above_ground) PointAttributes(s).pack(cloud.points, records, stride);
    }
    std::deque<CopcTreeNode*> page_queue;  // read before any node: they open the tree below
    std::deque<CopcTreeNode*> queue;
    std::deque<Done> done;
    std::size_t busy = 0;  // workers reading a page or a node
    bool stop = false;
    std::size_t points_arrived = 0;
    std::vector<std::thread> workers;

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
            wake.wait(lock,
                      [&] { return stop || ((!queue.empty() || !page_queue.empty()) && done.size() < kMaxWaiting); });
            if (stop) return;
            Done d;
            // queued and page_queued stay set until poll() takes the result.
            if (!page_queue.empty()) {
                d.node = page_queue.front();
                d.page = true;
                page_queue.pop_front();
            } else {
                d.node = queue.front();
                queue.pop_front();
            }
            ++busy;
            const io::CopcNode entry = d.node->entry;
            const io::CopcPage page = d.node->page;
            lock.unlock();
            if (d.page) {
                try {
                    d.entries = reader->readPage(page);
                } catch (const std::exception& e) {
                    d.error = e.what();
                    if (d.error.empty()) d.error = "the page cannot be read";
                }
                lock.lock();
                --busy;
                done.push_back(std::move(d));
                continue;
            }
            try {
                core::PointCloud cloud = reader->readNodeEntry(entry, io::SideRecords::Keep);
                d.fields = cloud.fields;
                d.from_elsewhere = cloud.foreign.has_value();
                prepare(cloud);
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
            --busy;
            if (d.points) points_arrived += d.points->points.size();
            done.push_back(std::move(d));
        }
    }

    /// The node of `key`, made with every node above it that is not there yet (a key may
    /// sit below keys the hierarchy leaves out). Frame thread, or the constructor.
    CopcTreeNode* ensure(const io::CopcKey& k) {
        CopcTreeNode* parent = nullptr;
        std::vector<PointNode*>* siblings = &roots;
        if (k.level > 0) {
            parent = ensure(parentKey(k));
            siblings = &parent->children_;
        }
        for (PointNode* c : *siblings)
            if (static_cast<CopcTreeNode*>(c)->key() == k) return static_cast<CopcTreeNode*>(c);
        const double side_m = 2.0 * info.halfsize_m / double(std::int64_t(1) << k.level);
        const glm::dvec3 centre(info.center_m[0], info.center_m[1], info.center_m[2]);
        core::Bounds b;
        b.lo = centre - glm::dvec3(info.halfsize_m) + side_m * glm::dvec3(k.x, k.y, k.z) - origin;
        b.hi = b.lo + glm::dvec3(side_m);
        nodes.push_back(std::make_unique<CopcTreeNode>(this, k, b));
        siblings->push_back(nodes.back().get());
        return nodes.back().get();
    }

    /// The level of the deepest node the tree has on the way to `k` (`k`'s own when it
    /// has it); -1 when it has no root yet.
    int deepestKnown(const io::CopcKey& k) const {
        const PointNode* at = nullptr;
        for (PointNode* r : roots)
            if (static_cast<const CopcTreeNode*>(r)->key() == io::CopcKey{}) at = r;
        if (!at) return -1;
        for (int level = 1; level <= k.level; ++level) {
            const int up = k.level - level;
            const io::CopcKey a{level, k.x >> up, k.y >> up, k.z >> up};
            const PointNode* next = nullptr;
            for (PointNode* c : at->children())
                if (static_cast<const CopcTreeNode*>(c)->key() == a) next = c;
            if (!next) return level - 1;
            at = next;
        }
        return k.level;
    }

    /// Why the page `where` (its entries `e`) cannot join the tree, or empty when it can: a
    /// node with points or a child page below the levels the cube resolves, or more nodes
    /// than the tree's bound allows. Counts the nodes the page would add (its keys and the
    /// keys above them the tree lacks) without making them, stopping past the bound, so a
    /// page refused costs no more than the bound.
    std::string refusal(const io::CopcPageEntries& e, const std::string& where) const {
        const auto too_deep = [&](const io::CopcKey& k, const char* what) {
            return where + ": " + what + " " + keyText(k) + " is at level " + std::to_string(k.level) +
                   "; allowed levels 0 to " + std::to_string(max_level) + " (deeper cells of its cube of halfsize " +
                   core::shownNumber(info.halfsize_m, 10) + " m are narrower than the file's coordinate step)";
        };
        for (const io::CopcNode& c : e.nodes)
            if (c.key.level > max_level) return too_deep(c.key, "node");
        for (const io::CopcPage& p : e.pages)
            if (p.key.level > max_level) return too_deep(p.key, "the child page of");
        const std::size_t room = max_nodes > nodes.size() ? max_nodes - nodes.size() : 0;
        std::set<io::CopcKey> fresh;  // at most `room` + 31 keys: the count stops past the bound
        const auto add = [&](const io::CopcKey& k) {
            const int known = deepestKnown(k);
            for (io::CopcKey a = k; a.level > known; a = parentKey(a))
                if (!fresh.insert(a).second) break;
            return fresh.size() <= room;
        };
        bool fits = true;
        for (std::size_t i = 0; fits && i < e.nodes.size(); ++i) fits = add(e.nodes[i].key);
        for (std::size_t i = 0; fits && i < e.pages.size(); ++i) fits = add(e.pages[i].key);
        if (fits) return {};
        return where + ": its " + std::to_string(e.nodes.size() + e.pages.size()) +
               " entries with points or child pages would take the tree past " + std::to_string(max_nodes) +
               " nodes (" + std::to_string(nodes.size()) + " held, " + std::to_string(kTreeNodeBytes) +
               " bytes each); allowed the hierarchy's " + mib(options.hierarchy_bytes) + " MiB (--memory-mb)";
    }

    static std::string keyText(const io::CopcKey& k) {
        return std::to_string(k.level) + "-" + std::to_string(k.x) + "-" + std::to_string(k.y) + "-" +
               std::to_string(k.z);
    }

    /// Adds one page's entries to the tree: its nodes with their chunks and counts, and
    /// its child pages as unexplored nodes (refusal() said they fit). An entry with no
    /// points makes no node: a node exists only on the way to points or to a page. An
    /// entry for a node already described (a page that repeats another's keys) is ignored.
    void addPage(const io::CopcPageEntries& e) {
        for (const io::CopcNode& c : e.nodes) {
            CopcTreeNode* n = ensure(c.key);
            if (n->entry.point_count != 0 || n->page.bytes > 0) continue;
            n->entry = c;
        }
        for (const io::CopcPage& p : e.pages) {
            CopcTreeNode* n = ensure(p.key);
            if (n->entry.point_count != 0 || n->page.bytes > 0) continue;
            n->page = p;
            ++stats.pages_unread;
        }
        ++stats.pages_read;
        stats.nodes = nodes.size();
        stats.hierarchy_bytes = nodes.size() * kTreeNodeBytes;
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
    const std::size_t workers = std::max<std::size_t>(1, options.workers);
    // The hierarchy's bound: a quarter for the pages being read at once (one per worker
    // and those waiting for poll()), the rest for the tree.
    const std::size_t page_entries =
        std::max<std::size_t>(1, options.hierarchy_bytes / 4 / (workers + kMaxWaiting) / kPageEntryBytes);
    m.max_nodes = (options.hierarchy_bytes - options.hierarchy_bytes / 4) / kTreeNodeBytes;
    m.reader = std::make_unique<io::CopcReader>(
        file, io::CopcHierarchy::by_page, page_entries,
        "its share of the hierarchy's " + mib(options.hierarchy_bytes) + " MiB, --memory-mb");
    m.origin = m.reader->origin();  // every node's points come in this frame
    m.info = m.reader->info();
    const glm::dvec3 scale = m.reader->scale();
    m.max_level = resolvedLevels(m.info.halfsize_m, std::min({scale.x, scale.y, scale.z}));
    m.total_points = std::size_t(m.reader->pointCount());
    m.stats.kind = "copc";
    m.stats.cache_bytes = options.cache_bytes;
    const io::CopcPageEntries root{m.reader->nodes(), {}, m.reader->pages()};
    const std::string refused = m.refusal(root, "copc: " + core::printable(m.file, 400) + ": the root hierarchy page");
    if (!refused.empty()) throw core::Error(refused);
    m.ensure(io::CopcKey{});
    m.addPage(root);
    for (std::size_t w = 0; w < workers; ++w) m.workers.emplace_back([&m] { m.work(); });
}

CopcSource::~CopcSource() {
    {
        std::lock_guard lock(impl_->mutex);
        impl_->stop = true;
    }
    impl_->wake.notify_all();
    for (std::thread& t : impl_->workers) t.join();
}

void CopcSource::select(const SourceView& view) {
    Impl& m = *impl_;
    ++m.round;
    const NodeSelection sel =
        selectNodes(m.roots, view.frusta, view.eye_local,
                    SelectionBudget{view.point_budget, m.options.cache_bytes, view.gpu_bytes}, view.focus);
    m.stats.wanted_points = sel.points;
    m.wanted = sel.wanted;
    m.pages_wanted = sel.unexplored.size();
    {
        // The queues follow the latest choice, most important first; what it no longer
        // wants is not read (a page or node being read or waiting for poll() stays so).
        std::lock_guard lock(m.mutex);
        for (CopcTreeNode* n : m.page_queue) n->page_queued = false;
        m.page_queue.clear();
        for (PointNode* p : sel.unexplored) {
            auto* n = static_cast<CopcTreeNode*>(p);
            if (!n->page_queued) {
                n->page_queued = true;
                m.page_queue.push_back(n);
            }
        }
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
        for (Impl::Done& d : arrived) (d.page ? d.node->page_queued : d.node->queued) = false;
        idle = m.queue.empty() && m.page_queue.empty() && m.busy == 0;
    }
    if (!arrived.empty()) m.wake.notify_one();
    std::size_t added = 0;
    for (Impl::Done& d : arrived) {
        CopcTreeNode* n = d.node;
        if (d.page) {
            if (n->page.bytes == 0 || n->page_failed) continue;  // read twice (asked again meanwhile)
            --m.stats.pages_unread;
            if (!d.error.empty()) {
                n->page_failed = true;
                ++m.stats.pages_failed;
                if (!m.options.quiet)
                    platform::printMessage("warning",
                                           "view: " + d.error + " (the nodes below it are skipped, the rest is drawn)");
                continue;
            }
            const std::string refused = m.refusal(
                d.entries, "copc: " + core::printable(m.file, 400) + ": the page of " + Impl::keyText(n->key()));
            if (!refused.empty()) {
                n->page_failed = true;
                ++m.stats.pages_failed;
                if (!m.options.quiet)
                    platform::printMessage("warning",
                                           "view: " + refused + " (the nodes below it are skipped, the rest is drawn)");
                continue;
            }
            n->page = {};
            m.addPage(d.entries);
            continue;
        }
        if (!d.points) {
            n->failed = true;
            ++m.stats.nodes_failed;
            if (!m.options.quiet)
                platform::printMessage("warning", "view: " + d.error + " (node skipped, the rest is drawn)");
            continue;
        }
        if (!m.fields_known) {  // the file's fields, as the first decoded node shows them
            m.fields = d.fields;
            m.from_elsewhere = d.from_elsewhere;
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
core::CloudFields CopcSource::fields() const {
    core::CloudFields f = impl_->fields;
    // A file from elsewhere whose colour values decoded so far are all 0 has no colours.
    if (f.rgb && impl_->from_elsewhere) {
        std::lock_guard lock(impl_->mutex);
        if (impl_->colours.depth() == io::ColourDepth::Zero) f.rgb = false;
    }
    return f;
}
bool CopcSource::fromElsewhere() const { return impl_->from_elsewhere; }
bool CopcSource::finished() const { return impl_->settled; }

std::size_t CopcSource::pointsArrived() const {
    std::lock_guard lock(impl_->mutex);
    return impl_->points_arrived;
}

std::optional<SourceStats> CopcSource::stats() const { return impl_->stats; }
std::span<PointNode* const> CopcSource::wanted() const { return impl_->wanted; }
std::size_t CopcSource::nodeCount() const { return impl_->nodes.size(); }
std::size_t CopcSource::pagesWanted() const { return impl_->pages_wanted; }
std::size_t CopcSource::totalPoints() const { return impl_->total_points; }

}  // namespace viewer
