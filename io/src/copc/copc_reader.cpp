// io/src/copc/copc_reader.cpp: io::CopcReader. The layout is read and checked once
// (copc_parse.cpp: the header, the info VLR, every hierarchy page and the chunk table);
// a node is then read by wrapping its chunk as a LAZ file of its own and decoding that
// with the LAS reader, so a node's points come exactly as the LAS reader gives them
// (through the file's origin: the whole file's header bounds decide it for every node,
// or its cube when the bounds lie far outside it)
// and LASzip decodes in the LAS reader's separate process.
#include <io/cloud_reader.hpp>
#include <io/copc.hpp>

#include "../cloud_decode.hpp"
#include "copc_parse.hpp"

#include <core/error.hpp>

#include <algorithm>
#include <array>
#include <cstring>
#include <fstream>
#include <mutex>
#include <utility>

namespace io {

using core::Error;

struct CopcReader::Impl {
    std::string prefix;
    std::unique_ptr<detail::ByteSource> source;
    detail::CopcLayout layout;
    std::mutex source_mutex;  // the file source reads through one window
};

namespace {

// Findings that leave every node readable as its entry declares it: the reader accepts
// them (the validator reports them), as readers of COPC written elsewhere should.
bool readable(const CopcFinding& f) {
    return f.rule == "info-reserved" || f.rule == "hierarchy-dead-space" || f.rule == "chunk-unreferenced" ||
           f.rule == "point-count" || f.rule == "bounds-within-cube";
}

}  // namespace

CopcReader::CopcReader(const std::filesystem::path& file, CopcHierarchy hierarchy, std::uint64_t page_entries_max,
                       std::string page_bound_source)
    : impl_(std::make_unique<Impl>()) {
    impl_->prefix = "copc: " + file.string();
    impl_->source = detail::fileSource(file, "copc");
    if (hierarchy == CopcHierarchy::by_page) impl_->layout.page_entries_max = page_entries_max;
    impl_->layout.page_bound_source = std::move(page_bound_source);
    std::vector<CopcFinding> findings;
    const bool ok = detail::parseCopc(*impl_->source, impl_->layout, findings, hierarchy);
    findings.erase(std::remove_if(findings.begin(), findings.end(), readable), findings.end());
    if (!findings.empty())
        throw Error(impl_->prefix + ": " + findings.front().rule + ": " + findings.front().message +
                    (findings.size() > 1 ? " (and " + std::to_string(findings.size() - 1) + " more findings)" : ""));
    if (!ok) throw Error(impl_->prefix + ": not a COPC file");
}

CopcReader::~CopcReader() = default;

const CopcInfo& CopcReader::info() const { return impl_->layout.info; }

const std::vector<CopcNode>& CopcReader::nodes() const { return impl_->layout.nodes; }

const std::vector<CopcKey>& CopcReader::emptyNodes() const { return impl_->layout.empty_nodes; }

const std::vector<CopcPage>& CopcReader::pages() const { return impl_->layout.pages; }

std::uint64_t CopcReader::pointCount() const { return impl_->layout.count; }

glm::dvec3 CopcReader::scale() const { return impl_->layout.scale; }

CopcPageEntries CopcReader::readPage(const CopcPage& page) const {
    CopcPageEntries entries;
    std::vector<CopcFinding> findings;
    bool ok = false;
    {
        std::lock_guard lock(impl_->source_mutex);
        ok = detail::parseCopcPage(*impl_->source, impl_->layout, page, entries, findings);
    }
    findings.erase(std::remove_if(findings.begin(), findings.end(), readable), findings.end());
    const std::string name = impl_->prefix + " page of " + detail::keyName(page.key);
    if (!findings.empty())
        throw Error(name + ": " + findings.front().rule + ": " + findings.front().message +
                    (findings.size() > 1 ? " (and " + std::to_string(findings.size() - 1) + " more findings)" : ""));
    if (!ok) throw Error(name + ": the page cannot be read");
    return entries;
}

glm::dvec3 CopcReader::origin() const {
    glm::dvec3 min, max;
    detail::frameBounds(impl_->layout, min, max);
    return detail::shiftFor(0.5 * (min + max));
}

core::PointCloud CopcReader::readNode(const CopcKey& key) const {
    const std::vector<CopcNode>& nodes = impl_->layout.nodes;
    const auto it = std::lower_bound(nodes.begin(), nodes.end(), key,
                                     [](const CopcNode& n, const CopcKey& k) { return n.key < k; });
    const std::string name = impl_->prefix + " node " + detail::keyName(key);
    if (it == nodes.end() || it->key != key) throw Error(name + ": the file has no node with points of that key");
    return readNodeEntry(*it);
}

core::PointCloud CopcReader::readNodeEntry(const CopcNode& node) const {
    return readNodeEntry(node, SideRecords::Drop);
}

core::PointCloud CopcReader::readNodeEntry(const CopcNode& node, SideRecords side) const {
    return readNodeEntry(node, side, PointFields::All);
}

core::PointCloud CopcReader::readNodeEntry(const CopcNode& node, SideRecords side, PointFields fields) const {
    const detail::CopcLayout& l = impl_->layout;
    const std::string name = impl_->prefix + " node " + detail::keyName(node.key);
    // An entry of this reader's pages lies in the point data (their checks); any other is
    // held to the same place before its bytes are read.
    const std::uint64_t end = l.table_at ? l.table_at : l.file_size;
    if (node.point_count <= 0 || node.byte_size <= 0 || node.offset < l.data_at + 8 || node.offset > end ||
        std::uint64_t(node.byte_size) > end - node.offset)
        throw Error(name + ": its chunk (" + std::to_string(node.byte_size) + " bytes at byte " +
                    std::to_string(node.offset) + ", " + std::to_string(node.point_count) +
                    " points) is not inside the point data");
    std::string laz;
    {
        std::lock_guard lock(impl_->source_mutex);  // the bytes copied; decoding runs unlocked
        laz = detail::nodeLaz(*impl_->source, l, node);
    }
    CloudReader reader(laz, name, side, fields);
    core::PointCloud cloud;
    cloud.origin = reader.origin();
    cloud.fields = reader.fields();
    cloud.points.reserve(std::size_t(node.point_count));
    if (const std::shared_ptr<const core::ForeignHeader> foreign = reader.foreignHeader()) {
        cloud.foreign.emplace();
        cloud.foreign->header = *foreign;
        while (reader.nextChunk(cloud.points, cloud.foreign->records, std::size_t(1) << 16)) {}
        return cloud;
    }
    while (reader.nextChunk(cloud.points, std::size_t(1) << 16)) {}
    return cloud;
}

bool isCopcFile(const std::filesystem::path& file) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(file, ec)) return false;
    std::array<char, 395> head{};
    std::ifstream in(file, std::ios::binary);
    if (!in.read(head.data(), head.size())) return false;
    constexpr std::size_t kFirstVlrUser = 375 + 2;  // after the header and the VLR's reserved field
    constexpr std::size_t kFirstVlrRecord = kFirstVlrUser + 16;
    const char user[16] = "copc";
    return std::memcmp(head.data(), "LASF", 4) == 0 && std::memcmp(head.data() + kFirstVlrUser, user, 16) == 0 &&
           static_cast<unsigned char>(head[kFirstVlrRecord]) == 1 && head[kFirstVlrRecord + 1] == 0;
}

}  // namespace io
