// tests/io/copc_test_file.hpp: a minimal valid COPC file made by hand for the COPC tests,
// independently of the project's COPC writer: LASzip compresses each node's points as a
// LAZ file of its own (one chunk), and the chunks are spliced after a LAS 1.4 header, the
// info VLR and LASzip's VLR (chunk size set to variable), followed by a variable chunk
// table coded here (LASzip's range coder: per chunk its point count in context 0, then
// its byte count in context 1, each predicted by the previous chunk's) and the
// hierarchy EVLR: a root page and one child page.
//
// The octree (centre (500064, 4000064, 64), halfsize 64): nodes 0-0-0-0, 1-0-0-0,
// 1-1-0-0, 2-3-3-3 and the empty 1-1-1-1 in the root page, which points to the child
// page of 1-0-1-0 holding 1-0-1-0, 2-0-2-0 and 2-1-3-1.
#pragma once
#include <io/copc.hpp>

#include <laszip/laszip_api.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace copc_test {

struct RawPoint {
    std::int32_t X = 0, Y = 0, Z = 0;
    double gps_time = 0.0;
    std::uint8_t return_number = 1, returns = 1, classification = 1;
    std::uint16_t intensity = 0, source = 0;
    std::uint16_t rgb[3] = {};
};

struct Node {
    io::CopcKey key;
    std::vector<RawPoint> points;
    std::size_t chunk_at = 0, chunk_bytes = 0;
    std::size_t entry_at = 0;  // its hierarchy entry's place in the file
};

struct File {
    std::string bytes;
    std::vector<Node> nodes;        // with points, in file order
    std::size_t info_at = 0;        // the info VLR's payload
    std::size_t laszip_vlr_at = 0;  // the LASzip VLR's header
    std::size_t data_at = 0;        // the 8 bytes giving the chunk table's place
    std::size_t table_at = 0;       // the chunk table
    std::size_t evlr_at = 0;        // the hierarchy EVLR's header
    std::size_t root_page_at = 0, root_page_size = 0;
    std::size_t child_page_at = 0, child_page_size = 0;
    std::size_t pointer_entry_at = 0;  // the root page's entry pointing to the child page
    std::size_t empty_entry_at = 0;    // the entry of the empty node 1-1-1-1
};

inline constexpr double kScale = 0.001;
inline constexpr double kCenter[3] = {500064.0, 4000064.0, 64.0};
inline constexpr double kHalf = 64.0;
inline constexpr double kOffset[3] = {500000.0, 4000000.0, 0.0};
inline constexpr double kGpsMin = 1000.0, kGpsMax = 1010.0;

template <typename T>
void put(std::string& s, std::size_t at, T v) {
    std::memcpy(s.data() + at, &v, sizeof v);
}
template <typename T>
T get(const std::string& s, std::size_t at) {
    T v;
    std::memcpy(&v, s.data() + at, sizeof v);
    return v;
}
template <typename T>
void append(std::string& s, T v) {
    s.append(reinterpret_cast<const char*>(&v), sizeof v);
}

// LAZ's range encoder with its adaptive models, as much as a chunk table needs.
class TableCoder {
  public:
    explicit TableCoder() {
        for (int c = 0; c < 2; ++c) k_.push_back(Symbols(33));
        for (int k = 1; k <= 32; ++k) corr_.push_back(Symbols(1u << (k < 8 ? k : 8)));
    }
    void integer(std::int32_t predicted, std::int32_t actual, int context) {
        const std::int32_t c = std::int32_t(std::uint32_t(actual) - std::uint32_t(predicted));
        std::uint32_t m = c <= 0 ? 0u - std::uint32_t(c) : std::uint32_t(c) - 1u;
        std::uint32_t k = 0;
        while (m) {
            m >>= 1;
            ++k;
        }
        symbol(k_[std::size_t(context)], k);
        if (k == 0) {
            bit(c != 0);
            return;
        }
        const std::uint32_t at = c < 0 ? std::uint32_t(c) + ((1u << k) - 1u) : std::uint32_t(c) - 1u;
        if (k <= 8) {
            symbol(corr_[k - 1], at);
        } else {
            symbol(corr_[k - 1], at >> (k - 8));
            raw(int(k - 8), at & ((1u << (k - 8)) - 1u));
        }
    }
    std::string finish() {
        const std::uint32_t before = base_;
        const bool big = length_ > 2 * kMin;
        base_ += big ? kMin : kMin >> 1;
        length_ = big ? kMin >> 1 : kMin >> 9;
        if (before > base_) carry();
        renorm();
        out_.append(big ? 3 : 2, '\0');
        return out_;
    }

  private:
    static constexpr std::uint32_t kMin = 1u << 24;
    struct Symbols {
        explicit Symbols(std::uint32_t symbols) : n(symbols), count(symbols, 1u), cum(symbols + 1, 0u) {
            cycle = n;
            update();
            left = cycle = (n + 6) >> 1;
        }
        void update() {
            if ((total += cycle) > (1u << 15)) {
                total = 0;
                for (auto& c : count) total += (c = (c + 1) >> 1);
            }
            std::uint32_t sum = 0;
            const std::uint32_t scale = 0x80000000u / total;
            for (std::uint32_t k = 0; k < n; ++k) {
                cum[k] = (scale * sum) >> 16;
                sum += count[k];
            }
            cycle = (5 * cycle) >> 2;
            if (cycle > (n + 6) << 3) cycle = (n + 6) << 3;
            left = cycle;
        }
        std::uint32_t n;
        std::vector<std::uint32_t> count, cum;
        std::uint32_t total = 0, cycle = 0, left = 0;
    };
    void symbol(Symbols& m, std::uint32_t s) {
        const std::uint32_t before = base_;
        if (s == m.n - 1) {
            const std::uint32_t x = m.cum[s] * (length_ >> 15);
            base_ += x;
            length_ -= x;
        } else {
            length_ >>= 15;
            const std::uint32_t x = m.cum[s] * length_;
            base_ += x;
            length_ = m.cum[s + 1] * length_ - x;
        }
        if (before > base_) carry();
        if (length_ < kMin) renorm();
        ++m.count[s];
        if (--m.left == 0) m.update();
    }
    void bit(bool b) {
        const std::uint32_t x = p0_ * (length_ >> 13);
        if (!b) {
            length_ = x;
        } else {
            const std::uint32_t before = base_;
            base_ += x;
            length_ -= x;
            if (before > base_) carry();
        }
        if (length_ < kMin) renorm();
        if (!b) ++zeros_;
        if (--bit_left_ == 0) {
            if ((bit_total_ += bit_cycle_) > (1u << 13)) {
                bit_total_ = (bit_total_ + 1) >> 1;
                zeros_ = (zeros_ + 1) >> 1;
                if (zeros_ == bit_total_) ++bit_total_;
            }
            p0_ = (zeros_ * (0x80000000u / bit_total_)) >> 18;
            bit_cycle_ = (5 * bit_cycle_) >> 2;
            if (bit_cycle_ > 64) bit_cycle_ = 64;
            bit_left_ = bit_cycle_;
        }
    }
    void raw(int bits, std::uint32_t v) {
        if (bits > 19) {
            raw(16, v & 0xFFFFu);
            raw(bits - 16, v >> 16);
            return;
        }
        const std::uint32_t before = base_;
        length_ >>= bits;
        base_ += v * length_;
        if (before > base_) carry();
        if (length_ < kMin) renorm();
    }
    void carry() {
        std::size_t i = out_.size();
        while (i > 0 && std::uint8_t(out_[i - 1]) == 0xFFu) out_[--i] = '\0';
        if (i > 0) out_[i - 1] = char(std::uint8_t(out_[i - 1]) + 1);
    }
    void renorm() {
        do {
            out_.push_back(char(base_ >> 24));
            base_ <<= 8;
        } while ((length_ <<= 8) < kMin);
    }
    std::vector<Symbols> k_, corr_;
    std::uint32_t zeros_ = 1, bit_total_ = 2, p0_ = 1u << 12, bit_cycle_ = 4, bit_left_ = 4;
    std::uint32_t base_ = 0, length_ = 0xFFFFFFFFu;
    std::string out_;
};

/// A variable chunk table: version 0, the count, then (points, bytes) per chunk, coded.
inline std::string variableChunkTable(const std::vector<std::pair<std::uint32_t, std::uint32_t>>& chunks) {
    std::string t;
    append<std::uint32_t>(t, 0);
    append<std::uint32_t>(t, std::uint32_t(chunks.size()));
    TableCoder c;
    for (std::size_t i = 0; i < chunks.size(); ++i) {
        c.integer(i ? std::int32_t(chunks[i - 1].first) : 0, std::int32_t(chunks[i].first), 0);
        c.integer(i ? std::int32_t(chunks[i - 1].second) : 0, std::int32_t(chunks[i].second), 1);
    }
    return t + c.finish();
}

inline void check(laszip_POINTER z, laszip_I32 rc, const char* what) {
    if (rc == 0) return;
    laszip_CHAR* m = nullptr;
    laszip_get_error(z, &m);
    throw std::runtime_error(std::string("copc_test: LASzip ") + what + ": " + (m ? m : "failed"));
}

// LASzip compresses `points` (format 7, one chunk) as a whole LAZ file in memory.
inline std::string lazOf(const std::vector<RawPoint>& points) {
    std::ostringstream out(std::ios::out | std::ios::binary);
    laszip_POINTER z = nullptr;
    if (laszip_create(&z) != 0) throw std::runtime_error("copc_test: LASzip could not be started");
    laszip_header_struct* h = nullptr;
    check(z, laszip_get_header_pointer(z, &h), "header");
    h->version_major = 1;
    h->version_minor = 4;
    h->header_size = 375;
    h->offset_to_point_data = 375;
    h->global_encoding = 1u << 4;
    h->point_data_format = 7;
    h->point_data_record_length = 36;
    h->x_scale_factor = h->y_scale_factor = h->z_scale_factor = kScale;
    h->x_offset = kOffset[0];
    h->y_offset = kOffset[1];
    h->z_offset = kOffset[2];
    check(z, laszip_set_chunk_size(z, 1u << 20), "chunk size");
    laszip_point_struct* q = nullptr;
    check(z, laszip_get_point_pointer(z, &q), "point");
    check(z, laszip_open_writer_stream(z, out, 1, 0), "open");
    for (const RawPoint& p : points) {
        q->X = p.X;
        q->Y = p.Y;
        q->Z = p.Z;
        q->intensity = p.intensity;
        q->extended_point_type = 1;
        q->extended_return_number = p.return_number;
        q->extended_number_of_returns = p.returns;
        q->return_number = p.return_number & 7u;
        q->number_of_returns = p.returns & 7u;
        q->extended_classification = p.classification;
        q->classification = p.classification & 31u;
        q->point_source_ID = p.source;
        q->gps_time = p.gps_time;
        for (int c = 0; c < 3; ++c) q->rgb[c] = p.rgb[c];
        check(z, laszip_write_point(z), "write");
    }
    check(z, laszip_close_writer(z), "close");
    laszip_destroy(z);
    return std::move(out).str();
}

// `n` points spread inside the cube of `key` (never on its faces), with every field set.
inline std::vector<RawPoint> pointsIn(const io::CopcKey& key, int n, int seed) {
    const double side = 2.0 * kHalf / double(1 << key.level);
    const int cell[3] = {key.x, key.y, key.z};
    std::vector<RawPoint> out;
    for (int i = 0; i < n; ++i) {
        const double u[3] = {(double((i * 37 + seed) % 101) + 0.5) / 101.0, (double((i * 53 + seed) % 89) + 0.5) / 89.0,
                             (double((i * 17 + seed) % 61) + 0.5) / 61.0};
        RawPoint p;
        std::int32_t* xyz[3] = {&p.X, &p.Y, &p.Z};
        for (int k = 0; k < 3; ++k) {
            const double w = kCenter[k] - kHalf + (double(cell[k]) + u[k]) * side;
            *xyz[k] = std::int32_t(std::lround((w - kOffset[k]) / kScale));
        }
        p.gps_time = kGpsMin + 10.0 * double((i * 7 + seed) % 1000) / 999.0;
        p.returns = std::uint8_t(1 + (i + seed) % 3);
        p.return_number = std::uint8_t(1 + i % p.returns);
        const std::uint8_t classes[4] = {1, 2, 6, 64};
        p.classification = classes[(i + seed) % 4];
        p.intensity = std::uint16_t(i * 131 + seed);
        p.source = std::uint16_t((i + seed) % 7);
        p.rgb[0] = std::uint16_t(((i * 3) & 255) * 257);
        p.rgb[1] = std::uint16_t(((seed * 5) & 255) * 257);
        p.rgb[2] = std::uint16_t((i & 255) * 257);
        out.push_back(p);
    }
    return out;
}

inline std::string entry(const io::CopcKey& k, std::uint64_t offset, std::int32_t bytes, std::int32_t count) {
    std::string e;
    append(e, k.level);
    append(e, k.x);
    append(e, k.y);
    append(e, k.z);
    append(e, offset);
    append(e, bytes);
    append(e, count);
    return e;
}

/// The valid file; `edit` may change the nodes' points before they are compressed.
/// `many`: instead of the two pages above, one root page of 73 nodes (the root and every
/// node of levels 1 and 2, 5 to 54 points each), so that the chunk table is long enough
/// for its coder's adaptive models to refresh several times.
inline File make(const std::function<void(std::vector<Node>&)>& edit = {}, bool many = false) {
    File f;
    if (!many) {
        const io::CopcKey keys[] = {{0, 0, 0, 0}, {1, 0, 0, 0}, {1, 1, 0, 0}, {2, 3, 3, 3},
                                    {1, 0, 1, 0}, {2, 0, 2, 0}, {2, 1, 3, 1}};
        const int counts[] = {300, 120, 90, 40, 150, 70, 55};
        for (int i = 0; i < 7; ++i) f.nodes.push_back({keys[i], pointsIn(keys[i], counts[i], 11 * i + 3)});
    } else {
        int i = 0;
        for (int level = 0; level <= 2; ++level)
            for (int x = 0; x < (1 << level); ++x)
                for (int y = 0; y < (1 << level); ++y)
                    for (int z = 0; z < (1 << level); ++z, ++i) {
                        const io::CopcKey k{level, x, y, z};
                        f.nodes.push_back({k, pointsIn(k, 5 + (i * 37) % 50, i)});
                    }
    }
    if (edit) edit(f.nodes);
    // Each node's chunk, and LASzip's VLR, from the files LASzip writes.
    std::vector<std::string> chunks;
    std::string laszip_vlr;
    for (const Node& n : f.nodes) {
        const std::string laz = lazOf(n.points);
        const std::uint32_t at = get<std::uint32_t>(laz, 96);
        const std::int64_t table = get<std::int64_t>(laz, at);
        chunks.push_back(laz.substr(at + 8, std::size_t(table) - at - 8));
        if (laszip_vlr.empty()) {
            // The VLRs between the header and the points: LASzip's is the only one.
            laszip_vlr = laz.substr(375, at - 375);
            if (get<std::uint32_t>(laz, 100) != 1) throw std::runtime_error("copc_test: LASzip wrote other VLRs");
        }
    }
    put<std::uint32_t>(laszip_vlr, 54 + 12, 0xFFFFFFFFu);  // variable chunks
    // Header, then the info VLR and LASzip's.
    std::string& b = f.bytes;
    b.assign(375, '\0');
    std::memcpy(b.data(), "LASF", 4);
    b[24] = 1;
    b[25] = 4;
    std::memcpy(b.data() + 26, "copc test", 9);
    std::memcpy(b.data() + 58, "tests/io/copc_test_file.hpp", 27);
    put<std::uint16_t>(b, 4 + 0, 0);    // file source id
    put<std::uint16_t>(b, 6, 1u << 4);  // global encoding: WKT bit, as point formats 6+ want
    put<std::uint16_t>(b, 94, 375);
    put<std::uint32_t>(b, 100, 2);
    b[104] = char(7 | 0x80);
    put<std::uint16_t>(b, 105, 36);
    for (int k = 0; k < 3; ++k) {
        put<double>(b, 131 + 8 * std::size_t(k), kScale);
        put<double>(b, 155 + 8 * std::size_t(k), kOffset[k]);
    }
    f.info_at = b.size() + 54;
    std::string vh(54, '\0');
    std::memcpy(vh.data() + 2, "copc", 4);
    put<std::uint16_t>(vh, 18, 1);
    put<std::uint16_t>(vh, 20, 160);
    std::memcpy(vh.data() + 22, "copc info", 9);
    b += vh;
    b.append(160, '\0');
    for (int k = 0; k < 3; ++k) put<double>(b, f.info_at + 8 * std::size_t(k), kCenter[k]);
    put<double>(b, f.info_at + 24, kHalf);
    put<double>(b, f.info_at + 32, 2.0 * kHalf / 128.0);
    put<double>(b, f.info_at + 56, kGpsMin);
    put<double>(b, f.info_at + 64, kGpsMax);
    f.laszip_vlr_at = b.size();
    b += laszip_vlr;
    f.data_at = b.size();
    put<std::uint32_t>(b, 96, std::uint32_t(f.data_at));
    b.append(8, '\0');
    // The chunks, the table, and what the header says of the points.
    std::vector<std::pair<std::uint32_t, std::uint32_t>> table;
    std::uint64_t total = 0, by_return[15] = {};
    std::int32_t lo[3] = {INT32_MAX, INT32_MAX, INT32_MAX}, hi[3] = {INT32_MIN, INT32_MIN, INT32_MIN};
    for (std::size_t i = 0; i < f.nodes.size(); ++i) {
        Node& n = f.nodes[i];
        n.chunk_at = b.size();
        n.chunk_bytes = chunks[i].size();
        b += chunks[i];
        table.emplace_back(std::uint32_t(n.points.size()), std::uint32_t(n.chunk_bytes));
        for (const RawPoint& p : n.points) {
            ++total;
            ++by_return[p.return_number - 1];
            const std::int32_t xyz[3] = {p.X, p.Y, p.Z};
            for (int k = 0; k < 3; ++k) {
                lo[k] = std::min(lo[k], xyz[k]);
                hi[k] = std::max(hi[k], xyz[k]);
            }
        }
    }
    f.table_at = b.size();
    put<std::int64_t>(b, f.data_at, std::int64_t(f.table_at));
    b += variableChunkTable(table);
    put<std::uint64_t>(b, 247, total);
    for (std::size_t r = 0; r < 15; ++r) put<std::uint64_t>(b, 255 + 8 * r, by_return[r]);
    for (int k = 0; k < 3; ++k) {
        put<double>(b, 179 + 16 * std::size_t(k), double(hi[k]) * kScale + kOffset[k]);
        put<double>(b, 187 + 16 * std::size_t(k), double(lo[k]) * kScale + kOffset[k]);
    }
    // The hierarchy EVLR: the root page, then the child page of 1-0-1-0 (none with `many`).
    f.evlr_at = b.size();
    f.root_page_at = f.evlr_at + 60;
    std::string root, child;
    const std::size_t in_root = many ? f.nodes.size() : 4;
    f.root_page_size = (many ? in_root : 6) * 32;
    f.child_page_at = f.root_page_at + f.root_page_size;
    for (std::size_t i = 0; i < f.nodes.size(); ++i) {
        Node& n = f.nodes[i];
        const std::string e = entry(n.key, n.chunk_at, std::int32_t(n.chunk_bytes), std::int32_t(n.points.size()));
        if (i < in_root) {
            n.entry_at = f.root_page_at + root.size();
            root += e;
        } else {
            n.entry_at = f.child_page_at + child.size();
            child += e;
        }
    }
    f.child_page_size = child.size();
    if (!many) {
        f.empty_entry_at = f.root_page_at + root.size();
        root += entry({1, 1, 1, 1}, 0, 0, 0);
        f.pointer_entry_at = f.root_page_at + root.size();
        root += entry({1, 0, 1, 0}, f.child_page_at, std::int32_t(f.child_page_size), -1);
    }
    std::string eh(60, '\0');
    std::memcpy(eh.data() + 2, "copc", 4);
    put<std::uint16_t>(eh, 18, 1000);
    put<std::uint64_t>(eh, 20, root.size() + child.size());
    std::memcpy(eh.data() + 28, "EPT hierarchy", 13);
    b += eh + root + child;
    put<std::uint64_t>(b, 235, f.evlr_at);
    put<std::uint32_t>(b, 243, 1);
    put<std::uint64_t>(b, f.info_at + 40, f.root_page_at);
    put<std::uint64_t>(b, f.info_at + 48, f.root_page_size);
    return f;
}

}  // namespace copc_test
