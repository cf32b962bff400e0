// laz_writer: LAZ 1.4 output with the chunks compressed in parallel.
//
// A LAZ file is the LAS header and VLRs, an 8-byte position of the chunk table, the
// chunks (each compressed on its own: a reader may start at any of them), then the table
// of the chunks' sizes. LASzip compresses on one thread and offers no way to hand it
// chunks made elsewhere, so this writer has LASzip compress each chunk of
// lazChunkPoints() points as a file of its own in memory, on worker threads, cuts the
// chunk's bytes out of it, writes the chunks in order, then the table
// (laz_chunk_table.cpp) and the header's counts and bounds. The result is the file LASzip
// writes by itself with the same chunk size, byte for byte (tested), whatever the thread
// count. The header and VLRs come from LASzip too: an empty file made at the start.
#include "las_record.hpp"
#include "format_writer.hpp"
#include "laz_chunk_table.hpp"
#include "laz_compress.hpp"

#include <core/error.hpp>
#include <platform/safe_file.hpp>

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <condition_variable>
#include <cstring>
#include <deque>
#include <exception>
#include <mutex>
#include <sstream>
#include <thread>
#include <vector>

namespace io::detail {

using core::CloudPoint;
using core::Error;

LaszipMemoryWriter::LaszipMemoryWriter(const LasRecord& record, laszip_U32 chunk_size)
    : record_(record), out_(std::ios::out | std::ios::binary) {
    if (laszip_create(&zip_) != 0 || !zip_) {
        if (zip_) laszip_destroy(zip_);
        throw Error(record_.where() + ": LASzip could not be started");
    }
    try {
        record_.setUp(zip_);
        record_.check(zip_, laszip_set_chunk_size(zip_, chunk_size), "chunk size");
        record_.check(zip_, laszip_get_point_pointer(zip_, &point_), "point");
        record_.check(zip_, laszip_open_writer_stream(zip_, out_, 1, 0), "open");
    } catch (...) {
        laszip_destroy(zip_);
        throw;
    }
    open_ = true;
}

LaszipMemoryWriter::~LaszipMemoryWriter() {
    if (open_) laszip_close_writer(zip_);
    laszip_destroy(zip_);
}

void LaszipMemoryWriter::write() { record_.check(zip_, laszip_write_point(zip_), "write"); }

LaszipFile LaszipMemoryWriter::finish() {
    open_ = false;
    record_.check(zip_, laszip_close_writer(zip_), "close");
    if (!out_) throw Error(record_.where() + ": LASzip's output in memory failed");
    LaszipFile f;
    f.bytes = std::move(out_).str();
    std::uint32_t at = 0;
    std::int64_t table = 0;
    if (f.bytes.size() >= 100) std::memcpy(&at, f.bytes.data() + 96, 4);
    if (at + std::size_t(8) <= f.bytes.size()) std::memcpy(&table, f.bytes.data() + at, 8);
    if (at < 375 || table < std::int64_t(at) + 8 || std::uint64_t(table) > f.bytes.size())
        throw Error(record_.where() + ": LASzip wrote a LAZ layout this writer does not know");
    f.point_data_at = at;
    f.table_at = std::size_t(table);
    return f;
}

LaszipFile compressWithLaszip(const LasRecord& record, std::span<const CloudPoint> points, std::uint64_t first_index,
                              LasInventory& inventory, laszip_U32 chunk_size, const unsigned char* foreign) {
    const std::size_t stride = foreign && record.foreign() ? record.foreign()->stride() : 0;
    LaszipMemoryWriter zip(record, chunk_size);
    // Counted on this thread's stack and merged once: callers keep the inventories of
    // chunks compressed at once side by side, and counting into them point by point
    // would make the threads fight over the cache lines they share.
    LasInventory counted;
    for (std::size_t i = 0; i < points.size(); ++i) {
        record.fill(zip.point(), points[i], first_index + i, &counted, stride > 0 ? foreign + i * stride : nullptr);
        zip.write();
    }
    LaszipFile f = zip.finish();
    inventory.merge(counted);
    return f;
}

namespace {

constexpr std::size_t kChunkPoints = 50000;  // LASzip's default chunk size
// A chunk's compressed bytes and LASzip's own buffers, per point, at most (LAZ takes
// 2-10 bytes per point; this leaves room for incompressible extra bytes).
constexpr std::size_t kCompressedBytesPerPoint = 24;

class LazWriter final : public FormatWriter {
  public:
    LazWriter(platform::TempFile& file, LasRecord record, const LasOptions& options)
        : record_(std::move(record)), file_(file.file()) {
        // The header and VLRs, as LASzip writes them for a file of these records.
        LasInventory none;
        const LaszipFile empty = compressWithLaszip(record_, {}, 0, none, laszip_U32(kChunkPoints));
        header_.assign(empty.bytes, 0, empty.point_data_at);
        empty_tail_.assign(empty.bytes, empty.point_data_at + 8, std::string::npos);
        write(header_.data(), header_.size());
        const std::int64_t placeholder = 0;  // the table's position, known at the end
        write(&placeholder, 8);
        const std::size_t chunk_bytes = std::size_t(lazChunkBytes());
        // Chunks queued or compressing, besides the one being filled.
        const std::size_t threads = std::size_t(std::max(options.threads, 0));
        const std::size_t chunks =
            options.memory_bytes > 0 ? std::size_t(options.memory_bytes / chunk_bytes) : threads + 2;
        in_flight_max_ = std::clamp<std::size_t>(chunks, 2, threads + 2) - 1;
        const int workers = std::min<int>(std::max(options.threads, 0), int(in_flight_max_));
        for (int i = 0; i < workers; ++i) workers_.emplace_back([this] { work(); });
    }

    ~LazWriter() override { stop(); }
    LazWriter(const LazWriter&) = delete;
    LazWriter& operator=(const LazWriter&) = delete;

    void append(std::span<const CloudPoint> points) override { appendForeign(points, nullptr); }

    // A chunk holds its points' side records beside them (none where `records` is null).
    void appendForeign(std::span<const CloudPoint> points, const unsigned char* records) override {
        const std::size_t stride = records && record_.foreign() ? record_.foreign()->stride() : 0;
        while (!points.empty()) {
            if (!filling_) {
                filling_ = std::make_unique<Job>();
                filling_->first_index = next_index_;
                if (!spare_.empty()) {  // a written chunk's buffer: no new pages to fault in
                    filling_->points = std::move(spare_.back());
                    spare_.pop_back();
                }
                filling_->points.reserve(kChunkPoints);
            }
            const std::size_t n = std::min(points.size(), kChunkPoints - filling_->points.size());
            filling_->points.insert(filling_->points.end(), points.begin(), points.begin() + std::ptrdiff_t(n));
            if (stride > 0) {
                filling_->foreign.insert(filling_->foreign.end(), records, records + n * stride);
                records += n * stride;
            }
            next_index_ += n;
            points = points.subspan(n);
            if (filling_->points.size() == kChunkPoints) submit();
        }
    }

    void finish() override {
        if (filling_) submit();
        while (!order_.empty()) writeOldest();
        stop();
        std::uint64_t table_at = header_.size() + 8;
        for (std::uint32_t b : chunk_bytes_) table_at += b;
        if (chunk_bytes_.empty()) {
            write(empty_tail_.data(), empty_tail_.size());  // LASzip's table of no chunks
        } else {
            const std::string table = lazChunkTable(chunk_bytes_);
            write(table.data(), table.size());
        }
        if (std::fflush(file_) != 0) throw Error(record_.where() + ": write failed: " + std::strerror(errno));
        const std::int64_t position = std::int64_t(table_at);
        if (::pwrite(fileno(file_), &position, 8, off_t(header_.size())) != 8)
            throw Error(record_.where() + ": writing the chunk table's position failed: " + std::strerror(errno));
        record_.patchHeader(fileno(file_), inventory_);
    }

  private:
    struct Job {
        std::vector<CloudPoint> points;
        std::vector<unsigned char> foreign;  // the points' side records, when kept
        std::uint64_t first_index = 0;
        bool taken = false, done = false;
        LaszipFile result;
        LasInventory inventory;
        std::exception_ptr error;
    };

    void run(Job& job) const {
        try {
            job.result =
                compressWithLaszip(record_, job.points, job.first_index, job.inventory, laszip_U32(kChunkPoints),
                                   job.foreign.empty() ? nullptr : job.foreign.data());
        } catch (...) {
            job.error = std::current_exception();
        }
    }

    void work() {
        std::unique_lock lock(mutex_);
        for (;;) {
            work_cv_.wait(lock, [&] { return stopping_ || !todo_.empty(); });
            if (stopping_) return;
            Job* job = todo_.front();
            todo_.pop_front();
            job->taken = true;
            lock.unlock();
            run(*job);
            lock.lock();
            job->done = true;
            done_cv_.notify_all();
        }
    }

    // Queues the chunk being filled; writes the oldest chunks once too many are held.
    void submit() {
        std::unique_ptr<Job> job = std::move(filling_);
        if (workers_.empty()) {
            run(*job);
            job->done = job->taken = true;
            order_.push_back(std::move(job));
        } else {
            std::lock_guard lock(mutex_);
            todo_.push_back(job.get());
            order_.push_back(std::move(job));
            work_cv_.notify_one();
        }
        while (order_.size() >= in_flight_max_ || (!order_.empty() && isDone(*order_.front()))) writeOldest();
    }

    bool isDone(const Job& job) {
        if (workers_.empty()) return job.done;
        std::lock_guard lock(mutex_);
        return job.done;
    }

    // Waits for the oldest chunk (compressing it here if no worker has taken it yet) and
    // appends its bytes to the file.
    void writeOldest() {
        Job& job = *order_.front();
        if (!workers_.empty()) {
            std::unique_lock lock(mutex_);
            if (!job.taken) {
                todo_.erase(std::find(todo_.begin(), todo_.end(), &job));
                job.taken = true;
                lock.unlock();
                run(job);
                lock.lock();
                job.done = true;
            }
            done_cv_.wait(lock, [&] { return job.done; });
        }
        if (job.error) std::rethrow_exception(job.error);
        const LaszipFile& f = job.result;
        const std::size_t begin = f.point_data_at + 8;
        if (f.bytes.compare(0, begin - 8, header_) != 0)
            throw Error(record_.where() + ": LASzip wrote a chunk under a different header");
        const std::size_t size = f.table_at - begin;
        if (size >= 0x80000000u) throw Error(record_.where() + ": a LAZ chunk of 2 GiB or more");
        write(f.bytes.data() + begin, size);
        chunk_bytes_.push_back(std::uint32_t(size));
        inventory_.merge(job.inventory);
        job.points.clear();
        spare_.push_back(std::move(job.points));
        order_.pop_front();
    }

    void write(const void* data, std::size_t size) {
        if (size > 0 && std::fwrite(data, 1, size, file_) != size)
            throw Error(record_.where() + ": write failed: " + std::strerror(errno));
    }

    void stop() {
        {
            std::lock_guard lock(mutex_);
            stopping_ = true;
        }
        work_cv_.notify_all();
        for (std::thread& t : workers_) t.join();
        workers_.clear();
    }

    LasRecord record_;
    std::FILE* file_;
    std::string header_;      // header and VLRs
    std::string empty_tail_;  // after the table's position in LASzip's empty file
    std::size_t in_flight_max_ = 1;
    std::unique_ptr<Job> filling_;
    std::vector<std::vector<CloudPoint>> spare_;  // buffers of written chunks, for the next ones
    std::uint64_t next_index_ = 0;
    std::deque<std::unique_ptr<Job>> order_;  // queued or compressed, in file order
    std::vector<std::uint32_t> chunk_bytes_;
    LasInventory inventory_;

    std::mutex mutex_;
    std::condition_variable work_cv_, done_cv_;
    std::deque<Job*> todo_;  // queued, not yet taken by a worker
    bool stopping_ = false;
    std::vector<std::thread> workers_;
};

}  // namespace

std::unique_ptr<FormatWriter> openLazWriter(platform::TempFile& file, const glm::dvec3& origin,
                                            const core::CloudFields& fields, const LasOptions& options) {
    LasRecord record("output: " + file.destination().string(), origin, fields, options);
    return std::make_unique<LazWriter>(file, std::move(record), options);
}

}  // namespace io::detail

namespace io {

std::size_t lazChunkPoints() { return detail::kChunkPoints; }

std::uint64_t lazChunkBytes() {
    return std::uint64_t(detail::kChunkPoints) * (sizeof(core::CloudPoint) + detail::kCompressedBytesPerPoint);
}

}  // namespace io
