// cloud_reader: picks the format by content, drops non-finite points, and builds the
// whole-cloud reads (readCloud, readCloudData) on the chunked reader.
#include <core/error.hpp>
#include <io/cloud_io.hpp>
#include <io/cloud_reader.hpp>
#include <platform/safe_file.hpp>

#include "cloud_decode.hpp"

#include <algorithm>
#include <future>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <stdexcept>

namespace io {

using core::CloudFields;
using core::CloudPoint;
using core::PointCloud;

namespace detail {

const char* moduleOf(ByteSource& source, const std::filesystem::path& name) {
    if (source.size() >= 4 && source.view(0, 4) == "LASF") return "las";
    if (source.size() >= 3 && source.view(0, 3) == "ply") return "ply";
    std::string ext = name.extension().string();
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    if (ext == ".las" || ext == ".laz") return "las";
    return "pcd";
}

}  // namespace detail

namespace {

// The module named in messages about a file that cannot be opened, by its extension.
const char* moduleFor(const std::filesystem::path& path) {
    std::string ext = path.extension().string();
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    if (ext == ".ply") return "ply";
    if (ext == ".las" || ext == ".laz") return "las";
    return "pcd";
}

std::unique_ptr<detail::FormatReader> open(detail::ByteSource& source, const std::string& module,
                                           const std::string& prefix, bool keep_foreign = false,
                                           PointFields fields = PointFields::All) {
    if (module == "las") return detail::openLas(source, prefix, keep_foreign, fields == PointFields::Positions);
    if (module == "ply") return detail::openPly(source, prefix);
    return detail::openPcd(source, prefix);
}

}  // namespace

CloudReader::CloudReader(const std::filesystem::path& path) : source_(detail::fileSource(path, moduleFor(path))) {
    const std::string module = detail::moduleOf(*source_, path);
    prefix_ = module + ": " + path.string();
    format_ = open(*source_, module, prefix_);
}

CloudReader::CloudReader(const std::filesystem::path& path, SideRecords side)
    : source_(detail::fileSource(path, moduleFor(path))) {
    const std::string module = detail::moduleOf(*source_, path);
    prefix_ = module + ": " + path.string();
    format_ = open(*source_, module, prefix_, side == SideRecords::Keep);
}

CloudReader::CloudReader(const std::filesystem::path& path, PointFields fields)
    : source_(detail::fileSource(path, moduleFor(path))) {
    const std::string module = detail::moduleOf(*source_, path);
    prefix_ = module + ": " + path.string();
    format_ = open(*source_, module, prefix_, false, fields);
}

CloudReader::CloudReader(std::string_view bytes, const std::filesystem::path& name, SideRecords side,
                         PointFields fields)
    : source_(detail::memorySource(bytes)) {
    const std::string module = detail::moduleOf(*source_, name);
    prefix_ = module + ": " + name.string();
    format_ = open(*source_, module, prefix_, side == SideRecords::Keep, fields);
}

CloudReader::~CloudReader() = default;

const glm::dvec3& CloudReader::origin() const { return format_->origin; }
const CloudFields& CloudReader::fields() const { return format_->fields; }
std::size_t CloudReader::declaredPoints() const { return format_->declared; }
std::size_t CloudReader::pointsBound() const { return format_->bound; }
std::shared_ptr<const core::ForeignHeader> CloudReader::foreignHeader() const { return format_->foreign; }

std::shared_ptr<const core::ForeignHeader> mergedForeignHeader(
    const std::vector<std::unique_ptr<CloudReader>>& readers) {
    if (readers.empty() || !readers.front()->foreignHeader()) return nullptr;
    const auto finest = [](const core::ForeignHeader& h) { return std::min({h.scale.x, h.scale.y, h.scale.z}); };
    std::shared_ptr<const core::ForeignHeader> best = readers.front()->foreignHeader();
    for (const auto& r : readers)
        if (const auto h = r->foreignHeader(); h && finest(*h) > 0.0 && finest(*h) < finest(*best)) best = h;
    if (best == readers.front()->foreignHeader()) return best;
    auto merged = std::make_shared<core::ForeignHeader>(*readers.front()->foreignHeader());
    merged->scale = best->scale;
    merged->offset = best->offset;
    return merged;
}

bool CloudReader::nextChunk(std::vector<CloudPoint>& out, std::vector<unsigned char>& records, std::size_t max_points) {
    if (!format_->foreign) return nextChunk(out, max_points);
    const std::size_t stride = format_->foreign->stride();
    const std::size_t old = out.size(), old_records = records.size();
    if (old_records != old * stride)
        throw std::logic_error("io: nextChunk: the side records do not match the points given");
    format_->foreign_out = &records;
    std::size_t n = 0;
    try {
        n = format_->next(out, std::max<std::size_t>(max_points, 1));
    } catch (...) {
        format_->foreign_out = nullptr;
        throw;
    }
    format_->foreign_out = nullptr;
    if (n == 0) return false;
    read_ += n;
    if (records.size() != out.size() * stride)
        throw std::logic_error("io: nextChunk: the reader gave side records that do not match its points");
    // Non-finite points leave with their records (LAS coordinates beyond float range).
    std::size_t kept = old;
    for (std::size_t i = old; i < out.size(); ++i) {
        const CloudPoint& p = out[i];
        if (!std::isfinite(p.position.x) || !std::isfinite(p.position.y) || !std::isfinite(p.position.z) ||
            (format_->fields.range && !std::isfinite(p.range_m)))
            continue;
        if (kept != i) {
            out[kept] = p;
            std::memmove(records.data() + kept * stride, records.data() + i * stride, stride);
        }
        ++kept;
    }
    dropped_ += out.size() - kept;
    out.resize(kept);
    records.resize(kept * stride);
    return true;
}

bool CloudReader::nextChunk(std::vector<CloudPoint>& out, std::size_t max_points) {
    if (format_->foreign) {
        // A reader keeping side records makes them whatever the caller asks: dropped here.
        std::vector<unsigned char> records;
        std::vector<CloudPoint> fresh;
        const bool more = nextChunk(fresh, records, max_points);
        out.insert(out.end(), fresh.begin(), fresh.end());
        return more;
    }
    const std::size_t old = out.size();
    const std::size_t n = format_->next(out, std::max<std::size_t>(max_points, 1));
    if (n == 0) return false;
    read_ += n;
    const bool range = format_->fields.range;
    const auto bad = [range](const CloudPoint& p) {
        return !std::isfinite(p.position.x) || !std::isfinite(p.position.y) || !std::isfinite(p.position.z) ||
               (range && !std::isfinite(p.range_m));
    };
    const auto first_bad = std::find_if(out.begin() + std::ptrdiff_t(old), out.end(), bad);
    if (first_bad != out.end()) {
        const auto end = std::remove_if(first_bad, out.end(), bad);
        dropped_ += std::size_t(out.end() - end);
        out.erase(end, out.end());
    }
    return true;
}

std::string CloudReader::warning() const {
    std::string w;
    if (dropped_ > 0)
        w = prefix_ + ": dropped " + std::to_string(dropped_) + " of " + std::to_string(read_) +
            " points with a non-finite x, y, z or range (NaN or inf)";
    if (const detail::DecodeStats& s = format_->stats; s.unknown_classes > 0)
        w += (w.empty() ? prefix_ + ": " : std::string("; ")) + std::to_string(s.unknown_classes) +
             " points have an ASPRS class this reader does not know (the first: " + std::to_string(s.first_unknown) +
             "); read as environment";
    return w;
}

namespace {

PointCloud readAll(CloudReader& reader) {
    PointCloud cloud;
    cloud.origin = reader.origin();
    cloud.fields = reader.fields();
    cloud.points.reserve(reader.pointsBound());
    if (const auto header = reader.foreignHeader()) {
        cloud.foreign.emplace();
        cloud.foreign->header = *header;
        while (reader.nextChunk(cloud.points, cloud.foreign->records, std::size_t(1) << 20)) {}
        return cloud;
    }
    while (reader.nextChunk(cloud.points, std::size_t(1) << 20)) {}
    return cloud;
}

}  // namespace

PointCloud readCloudData(std::string_view bytes, const std::filesystem::path& name) {
    CloudReader reader(bytes, name);
    return readAll(reader);
}

PointCloud readCloud(const std::filesystem::path& path) {
    CloudReader reader(path);
    return readCloud(reader);
}

PointCloud readCloud(CloudReader& reader) {
    PointCloud cloud = readAll(reader);
    if (const std::string w = reader.warning(); !w.empty()) platform::printMessage("warning", w);
    return cloud;
}

void forEachChunk(CloudReader& reader,
                  const std::function<void(std::vector<CloudPoint>&, std::vector<unsigned char>&)>& fn) {
    std::vector<CloudPoint> chunk, next;
    std::vector<unsigned char> records, next_records;
    bool more = reader.nextChunk(chunk, records);
    while (more) {
        std::future<bool> reading = std::async(std::launch::async, [&] {
            next.clear();
            next_records.clear();
            return reader.nextChunk(next, next_records);
        });
        try {
            fn(chunk, records);
        } catch (...) {
            reading.wait();
            throw;
        }
        more = reading.get();
        std::swap(chunk, next);
        std::swap(records, next_records);
    }
}

void forEachChunk(CloudReader& reader, const std::function<void(std::vector<CloudPoint>&)>& fn) {
    std::vector<CloudPoint> chunk, next;
    bool more = reader.nextChunk(chunk);
    while (more) {
        std::future<bool> reading = std::async(std::launch::async, [&] {
            next.clear();
            return reader.nextChunk(next);
        });
        try {
            fn(chunk);
        } catch (...) {
            reading.wait();
            throw;
        }
        more = reading.get();
        std::swap(chunk, next);
    }
}

}  // namespace io
