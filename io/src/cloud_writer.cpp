// cloud_writer: the format names, and CloudWriter: a temporary file beside the output that
// one format's writer fills (pcd/, ply/, las/, copc/: format_writer.hpp) and that is renamed into
// place on commit. The readers are behind io::CloudReader (cloud_reader.cpp).
#include <core/error.hpp>
#include <io/cloud_io.hpp>
#include <platform/atomic_file.hpp>
#include <platform/safe_file.hpp>

#include "format_writer.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <stdexcept>

namespace io {

using core::PointCloud;

using core::Error;

CloudFormat parseCloudFormat(std::string_view name, std::string_view parameter) {
    for (CloudFormat f : {CloudFormat::PcdBinary, CloudFormat::PcdAscii, CloudFormat::PlyBinary, CloudFormat::PlyAscii,
                          CloudFormat::Las, CloudFormat::Laz, CloudFormat::Copc})
        if (name == cloudFormatName(f)) return f;
    throw Error(std::string(parameter) + ": format '" + core::printable(name, 40) +
                "' is not one of pcd, pcd-ascii, ply, ply-ascii, las, laz, copc");
}

const char* cloudFormatName(CloudFormat format) {
    switch (format) {
        case CloudFormat::PcdBinary: return "pcd";
        case CloudFormat::PcdAscii: return "pcd-ascii";
        case CloudFormat::PlyBinary: return "ply";
        case CloudFormat::PlyAscii: return "ply-ascii";
        case CloudFormat::Las: return "las";
        case CloudFormat::Laz: return "laz";
        case CloudFormat::Copc: return "copc";
    }
    return "pcd";
}

CloudFormat formatForPath(const std::filesystem::path& path, std::string_view parameter) {
    const auto lower = [](std::string s) {
        std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
        return s;
    };
    const std::string name = lower(path.filename().string());
    if (name.size() > 9 && name.ends_with(".copc.laz")) return CloudFormat::Copc;  // never a plain LAZ
    const std::string ext = lower(path.extension().string());
    if (ext.empty() || ext == ".pcd") return CloudFormat::PcdBinary;  // no extension: PCD, the default
    if (ext == ".ply") return CloudFormat::PlyBinary;
    if (ext == ".las") return CloudFormat::Las;
    if (ext == ".laz") return CloudFormat::Laz;
    throw Error(std::string(parameter) + ": " + core::printable(path.string(), 200, true) + ": extension '" +
                core::printable(ext, 40, true) + "' is not one of .pcd, .ply, .las, .laz, .copc.laz");
}

CloudWriter::CloudWriter(std::filesystem::path path, CloudFormat format, glm::dvec3 origin, core::CloudFields fields,
                         const LasOptions& las, const CopcOptions* copc)
    : path_(std::move(path)) {
    platform::checkWritableDestination(path_);
    if (!std::isfinite(origin.x) || !std::isfinite(origin.y) || !std::isfinite(origin.z))
        throw Error("output: " + path_.string() + ": the cloud origin is not finite");
    foreign_stride_ = las.foreign ? las.foreign->stride() : 0;
    temp_ = std::make_unique<platform::TempFile>(path_);
    switch (format) {
        case CloudFormat::PcdBinary: writer_ = detail::openPcdWriter(*temp_, false, origin, fields); break;
        case CloudFormat::PcdAscii: writer_ = detail::openPcdWriter(*temp_, true, origin, fields); break;
        case CloudFormat::PlyBinary: writer_ = detail::openPlyWriter(*temp_, false, origin, fields); break;
        case CloudFormat::PlyAscii: writer_ = detail::openPlyWriter(*temp_, true, origin, fields); break;
        case CloudFormat::Las: writer_ = detail::openLasWriter(*temp_, origin, fields, las); break;
        case CloudFormat::Laz: writer_ = detail::openLazWriter(*temp_, origin, fields, las); break;
        case CloudFormat::Copc:
            writer_ = detail::openCopcWriter(*temp_, origin, fields, las, copc ? *copc : CopcOptions{});
            break;
    }
}

// The TempFile removes the temporary when destroyed uncommitted.
CloudWriter::~CloudWriter() = default;

void CloudWriter::append(std::span<const core::CloudPoint> points) {
    if (!writer_) throw Error("output: " + path_.string() + ": append after commit");
    writer_->append(points);
    count_ += points.size();
}

void CloudWriter::append(std::span<const core::CloudPoint> points, std::span<const unsigned char> records) {
    if (!writer_) throw Error("output: " + path_.string() + ": append after commit");
    if (foreign_stride_ == 0) {
        writer_->append(points);
    } else {
        if (records.size() != points.size() * foreign_stride_)
            throw std::logic_error("io: " + std::to_string(records.size()) +
                                   " bytes are not one side record for each of " + std::to_string(points.size()) +
                                   " points of " + path_.string());
        writer_->appendForeign(points, records.data());
    }
    count_ += points.size();
}

int CloudWriter::prescanPasses(std::uint64_t points, const core::Bounds* positions) {
    if (!writer_) throw Error("output: " + path_.string() + ": prescan after commit");
    return count_ == 0 ? writer_->prescanPasses(points, positions) : 0;
}

void CloudWriter::prescan(int pass, std::span<const core::CloudPoint> points) {
    if (!writer_) throw Error("output: " + path_.string() + ": prescan after commit");
    writer_->prescan(pass, points);
}

bool CloudWriter::rewritable() const { return writer_ && writer_->rewritable(); }

std::size_t CloudWriter::recordBytes() const { return writer_ ? writer_->recordBytes() : 0; }

std::size_t CloudWriter::readBack(std::uint64_t first, std::span<core::CloudPoint> out) {
    if (!writer_) throw Error("output: " + path_.string() + ": read back after commit");
    if (!writer_->rewritable()) throw std::logic_error("io: the points of " + path_.string() + " cannot be read back");
    if (first >= count_) return 0;
    return writer_->readBack(first, out.first(std::size_t(std::min<std::uint64_t>(out.size(), count_ - first))));
}

void CloudWriter::packRecords(std::span<const core::CloudPoint> points, char* out) const {
    if (!writer_ || !writer_->rewritable())
        throw std::logic_error("io: the records of " + path_.string() + " cannot be packed apart");
    writer_->packRecords(points, out);
}

void CloudWriter::appendRecords(std::span<const char> records) {
    if (!writer_) throw Error("output: " + path_.string() + ": append after commit");
    const std::size_t size = writer_->recordBytes();
    if (!writer_->rewritable() || size == 0 || records.size() % size != 0)
        throw std::logic_error("io: " + std::to_string(records.size()) + " bytes are not whole records of " +
                               path_.string());
    writer_->appendRecords(records.data(), records.size() / size);
    count_ += records.size() / size;
}

void CloudWriter::rewrite(std::uint64_t first, std::span<const core::CloudPoint> points) {
    if (!writer_) throw Error("output: " + path_.string() + ": rewrite after commit");
    if (!writer_->rewritable()) throw std::logic_error("io: the points of " + path_.string() + " cannot be rewritten");
    if (first > count_ || points.size() > count_ - first)
        throw std::logic_error("io: rewrite past the points appended to " + path_.string());
    writer_->rewrite(first, points);
}

void CloudWriter::commit() {
    if (!writer_) throw Error("output: " + path_.string() + ": commit called twice");
    const std::unique_ptr<detail::FormatWriter> writer = std::move(writer_);
    try {
        writer->finish();
    } catch (...) {
        temp_->discard();
        throw;
    }
    temp_->commit();  // flush, close, rename over path_ (or remove the temporary and throw)
}

void writeCloud(const std::filesystem::path& path, const PointCloud& cloud, CloudFormat format, const LasOptions& las) {
    const bool foreign =
        cloud.foreign && cloud.foreign->records.size() == cloud.points.size() * cloud.foreign->header.stride();
    if (!foreign) {
        CloudWriter writer(path, format, cloud.origin, cloud.fields, las);
        writer.append(cloud.points);
        writer.commit();
        return;
    }
    LasOptions with = las;
    with.foreign = std::make_shared<const core::ForeignHeader>(cloud.foreign->header);
    CloudWriter writer(path, format, cloud.origin, cloud.fields, with);
    writer.append(cloud.points, cloud.foreign->records);
    writer.commit();
}

}  // namespace io
