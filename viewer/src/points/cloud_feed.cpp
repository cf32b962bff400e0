// viewer/src/points/cloud_feed.cpp: the producer/consumer queue that streams a cloud into the viewer.
#include <viewer/cloud_feed.hpp>

#include "points/file_colours.hpp"
#include "points/point_attributes.hpp"

#include <core/error.hpp>
#include <io/cloud_reader.hpp>
#include <platform/safe_file.hpp>

#include <algorithm>
#include <cstdio>
#include <exception>
#include <span>
#include <utility>

namespace viewer {

CloudFeed::~CloudFeed() {
    if (loader_.joinable()) loader_.join();
}

void CloudFeed::setOrigin(const glm::dvec3& origin) {
    std::lock_guard lock(mutex_);
    origin_ = origin;
}

void CloudFeed::setFields(const core::CloudFields& fields, bool from_elsewhere) {
    std::lock_guard lock(mutex_);
    fields_ = fields;
    from_elsewhere_ = from_elsewhere;
}

void CloudFeed::enableLodOrder(const LodOptions& options) {
    std::lock_guard lock(mutex_);
    lod_order_ = true;
    lod_options_ = options;
}

void CloudFeed::append(std::vector<core::CloudPoint> chunk) {
    const std::size_t n = chunk.size();
    FeedChunk item;
    bool lod = false;
    LodOptions options;
    {
        std::lock_guard lock(mutex_);
        lod = lod_order_;
        options = lod_options_;
    }
    if (lod) item.cells = buildLodOrder(chunk, options);  // outside the lock: the producer's time
    item.points = std::move(chunk);
    {
        std::lock_guard lock(mutex_);
        pending_.push_back(std::move(item));
    }
    arrived_ += n;
}

void CloudFeed::finish(std::string error) {
    {
        std::lock_guard lock(mutex_);
        error_ = std::move(error);
    }
    finished_ = true;
    finished_.notify_all();
}

std::vector<FeedChunk> CloudFeed::take() {
    std::lock_guard lock(mutex_);
    return std::exchange(pending_, {});
}

glm::dvec3 CloudFeed::origin() const {
    std::lock_guard lock(mutex_);
    return origin_;
}

core::CloudFields CloudFeed::fields() const {
    std::lock_guard lock(mutex_);
    core::CloudFields f = fields_;
    if (colours_zero_) f.rgb = false;
    return f;
}

bool CloudFeed::fromElsewhere() const {
    std::lock_guard lock(mutex_);
    return from_elsewhere_;
}

std::string CloudFeed::error() const {
    std::lock_guard lock(mutex_);
    return error_;
}

void CloudFeed::feedCloud(core::PointCloud cloud, std::size_t chunk_points) {
    setOrigin(cloud.origin);
    setFields(cloud.fields, cloud.foreign.has_value());
    chunk_points = std::max<std::size_t>(chunk_points, 1);
    // A cloud without heights above ground carries its class, intensity and returns in
    // their place (point_attributes.hpp), as a file read by feedFile does.
    PointAttributes attributes;
    for (std::size_t i = 0; i < cloud.points.size(); i += chunk_points) {
        const std::size_t end = std::min(cloud.points.size(), i + chunk_points);
        if (!cloud.fields.height_above_ground) {
            const std::size_t stride = cloud.foreign ? cloud.foreign->header.stride() : 0;
            std::span<const unsigned char> records;
            if (cloud.foreign) records = std::span<const unsigned char>(cloud.foreign->records);
            records = records.subspan(std::min(records.size(), i * stride));
            attributes.pack(std::span(cloud.points).subspan(i, end - i), records, stride);
        }
        append(std::vector<core::CloudPoint>(cloud.points.begin() + static_cast<std::ptrdiff_t>(i),
                                             cloud.points.begin() + static_cast<std::ptrdiff_t>(end)));
    }
    finish();
}

void CloudFeed::feedFile(const std::filesystem::path& path, std::size_t chunk_points) {
    try {
        // The same reader as io::readCloud: the header is checked whole before the
        // first chunk, so a bad file is refused before anything is shown.
        // A file from elsewhere gives its 16-bit colours too, to be shown at their depth.
        io::CloudReader reader(path, io::SideRecords::Keep);
        setOrigin(reader.origin());
        const auto foreign = reader.foreignHeader();
        setFields(reader.fields(), foreign != nullptr);
        chunk_points = std::max<std::size_t>(chunk_points, 1);
        FileColours colours;
        PointAttributes attributes;
        std::vector<unsigned char> records;
        for (;;) {
            std::vector<core::CloudPoint> chunk;
            chunk.reserve(std::min(chunk_points, reader.pointsBound()));
            records.clear();
            if (!reader.nextChunk(chunk, records, chunk_points)) break;
            if (foreign && reader.fields().rgb) {
                colours.recolour(chunk, records, foreign->stride());
                std::lock_guard lock(mutex_);
                colours_zero_ = colours.depth() == io::ColourDepth::Zero;
            }
            // Without heights above ground, their place holds the class, intensity and returns.
            if (!reader.fields().height_above_ground) attributes.pack(chunk, records, foreign ? foreign->stride() : 0);
            if (!chunk.empty()) append(std::move(chunk));
        }
        if (const std::string warning = reader.warning(); !warning.empty()) platform::printMessage("warning", warning);
        if (pointsArrived() == 0) {
            finish(reader.where() + ": holds no points to show");
            return;
        }
        finish();
    } catch (const std::exception& e) {
        finish(e.what());
    }
}

void CloudFeed::startFileLoader(std::filesystem::path path, std::size_t chunk_points) {
    loader_ = std::thread([this, path = std::move(path), chunk_points] { feedFile(path, chunk_points); });
}

}  // namespace viewer
