// viewer/src/points/open_point_source.cpp: the choice of a cloud file's point source and
// its opening (viewer/open_point_source.hpp).
#include <viewer/open_point_source.hpp>

#include <core/error.hpp>
#include <io/copc.hpp>

#include <utility>

namespace viewer {

SourcePath choosePath(const std::filesystem::path& cloud, CloudIndexer* indexer, EveryPoint every_point) {
    if (every_point == EveryPoint::Needed) return SourcePath::Whole;
    if (io::isCopcFile(cloud)) return SourcePath::Copc;
    if (indexer != nullptr && indexer->wantsIndex(cloud)) return SourcePath::Indexed;
    return SourcePath::Whole;
}

OpenedCloud openPointSource(const std::filesystem::path& cloud, SourcePath path, const OpenSourceOptions& options) {
    OpenedCloud opened;
    opened.path = path;
    if (path == SourcePath::Whole) {
        opened.file = cloud;
        if (options.feed != nullptr) {
            options.feed->startFileLoader(cloud);
            return opened;
        }
        opened.feed = std::make_unique<CloudFeed>();
        opened.feed->enableLodOrder();  // each chunk's LOD order on the loader thread, not in the frame loop
        opened.feed->startFileLoader(cloud);
        return opened;
    }
    if (path == SourcePath::Copc) {
        opened.file = cloud;
        opened.copc = std::make_unique<CopcSource>(cloud, options.copc);
        return opened;
    }
    if (options.indexer == nullptr) throw core::Error("view: no indexer for a cloud file to be read through its index");
    opened.file = options.indexer->index(cloud, std::string());
    try {
        opened.copc = std::make_unique<CopcSource>(opened.file, options.copc);
    } catch (const core::Error& e) {
        // An index that does not open (a cached one damaged on disk) is written again, once.
        std::filesystem::path again = options.indexer->index(cloud, e.what());
        if (again.empty()) throw;
        opened.file = std::move(again);
        opened.copc = std::make_unique<CopcSource>(opened.file, options.copc);
    }
    return opened;
}

}  // namespace viewer
