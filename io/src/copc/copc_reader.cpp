// io/src/copc/copc_reader.cpp: io::CopcReader. The layout is read and checked once
// (copc_parse.cpp: the header, the info VLR, every hierarchy page and the chunk table);
// a node is then read by wrapping its chunk as a LAZ file of its own and decoding that
// with the LAS reader, so a node's points come exactly as the LAS reader gives them
// (through the file's origin: the whole file's header bounds decide it for every node)
// and LASzip decodes in the LAS reader's separate process.
#include <io/cloud_reader.hpp>
#include <io/copc.hpp>

#include "../cloud_decode.hpp"
#include "copc_parse.hpp"

#include <core/error.hpp>

#include <algorithm>

namespace io {

using core::Error;

struct CopcReader::Impl {
    std::string prefix;
    std::unique_ptr<detail::ByteSource> source;
    detail::CopcLayout layout;
};

namespace {

// Findings that leave every node readable as its entry declares it: the reader accepts
// them (the validator reports them), as readers of COPC written elsewhere should.
bool readable(const CopcFinding& f) {
    return f.rule == "info-reserved" || f.rule == "hierarchy-dead-space" || f.rule == "chunk-unreferenced" ||
           f.rule == "point-count" || f.rule == "bounds-within-cube";
}

}  // namespace

CopcReader::CopcReader(const std::filesystem::path& file) : impl_(std::make_unique<Impl>()) {
    impl_->prefix = "copc: " + file.string();
    impl_->source = detail::fileSource(file, "copc");
    std::vector<CopcFinding> findings;
    const bool ok = detail::parseCopc(*impl_->source, impl_->layout, findings);
    findings.erase(std::remove_if(findings.begin(), findings.end(), readable), findings.end());
    if (!findings.empty())
        throw Error(impl_->prefix + ": " + findings.front().rule + ": " + findings.front().message +
                    (findings.size() > 1 ? " (and " + std::to_string(findings.size() - 1) + " more findings)" : ""));
    if (!ok) throw Error(impl_->prefix + ": not a COPC file");
}

CopcReader::~CopcReader() = default;

const CopcInfo& CopcReader::info() const { return impl_->layout.info; }

const std::vector<CopcNode>& CopcReader::nodes() const { return impl_->layout.nodes; }

glm::dvec3 CopcReader::origin() const { return detail::shiftFor(0.5 * (impl_->layout.min + impl_->layout.max)); }

core::PointCloud CopcReader::readNode(const CopcKey& key) const {
    const std::vector<CopcNode>& nodes = impl_->layout.nodes;
    const auto it = std::lower_bound(nodes.begin(), nodes.end(), key,
                                     [](const CopcNode& n, const CopcKey& k) { return n.key < k; });
    const std::string name = impl_->prefix + " node " + detail::keyName(key);
    if (it == nodes.end() || it->key != key) throw Error(name + ": the file has no node with points of that key");
    const std::string laz = detail::nodeLaz(*impl_->source, impl_->layout, *it);
    CloudReader reader(laz, name);
    core::PointCloud cloud;
    cloud.origin = reader.origin();
    cloud.fields = reader.fields();
    cloud.points.reserve(std::size_t(it->point_count));
    while (reader.nextChunk(cloud.points, std::size_t(1) << 16)) {}
    return cloud;
}

}  // namespace io
