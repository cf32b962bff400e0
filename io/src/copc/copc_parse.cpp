// io/src/copc/copc_parse.cpp: see copc_parse.hpp. The rules come from the COPC 1.0
// specification (copc.io), LAS 1.4 R15 and the LAZ chunk table as LASzip writes it; the
// rule names are those of docs/formats.md ("Checking COPC").
#include "copc_parse.hpp"

#include "../las/laz_chunk_table.hpp"
#include "../las/laz_models.hpp"

#include <core/error.hpp>
#include <core/frames.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <deque>
#include <map>
#include <set>

namespace io::detail {

namespace {

constexpr std::size_t kHeaderSize = 375;
constexpr std::size_t kVlrHeader = 54;
constexpr std::size_t kEvlrHeader = 60;
constexpr std::size_t kInfoSize = 160;
constexpr std::size_t kEntrySize = 32;
constexpr std::uint32_t kVariableChunks = 0xFFFFFFFFu;
constexpr std::array<std::size_t, 11> kMinRecord = {20, 28, 26, 34, 57, 63, 30, 36, 38, 59, 67};
constexpr int kMaxLevel = 30;  // 2^level cells per axis must fit an int32 key

template <typename T>
T le(std::string_view bytes, std::size_t at) {
    T v;
    std::memcpy(&v, bytes.data() + at, sizeof v);
    return v;
}

template <typename T>
void put(std::string& bytes, std::size_t at, T v) {
    std::memcpy(bytes.data() + at, &v, sizeof v);
}

// `n` bytes at `at`, or false when they are not all inside the file.
bool fetch(ByteSource& source, std::uint64_t at, std::size_t n, std::string& out) {
    if (at > source.size() || n > source.size() - at) return false;
    out.assign(source.view(at, n));
    return true;
}

std::string n2s(std::uint64_t v) { return std::to_string(v); }
std::string num(double v) { return core::shownNumber(v, 10); }

std::string userId(std::string_view header) { return std::string(header.data() + 2, strnlen(header.data() + 2, 16)); }

// The decoding half of LAZ's range coder, enough to read a chunk table: the models
// (las/laz_models.hpp) refresh as the encoder's do (las/laz_chunk_table.cpp is the encoding
// half), and the integer corrector. Reading past the coded bytes yields zeros and sets
// `overrun`.
class RangeDecoder {
  public:
    explicit RangeDecoder(std::string_view coded) : coded_(coded) {
        for (int i = 0; i < 4; ++i) value_ = (value_ << 8) | byte();
    }
    bool overrun = false;

    std::uint32_t decode(SymbolModel& m) {
        std::uint32_t sym = 0, x = 0, y = length_, n = m.symbols();
        length_ >>= kLazSymbolShift;
        // The largest symbol whose interval starts at or below value_.
        for (std::uint32_t k = n >> 1; k != sym; k = (sym + n) >> 1) {
            const std::uint32_t z = length_ * m.low(k);
            if (z > value_) {
                n = k;
                y = z;
            } else {
                sym = k;
                x = z;
            }
        }
        value_ -= x;
        length_ = y - x;
        if (length_ < kLazMinLength) renormalise();
        m.saw(sym);
        return sym;
    }
    bool decode(BitModel& m) {
        const std::uint32_t x = m.zeroProbability() * (length_ >> kLazBitShift);
        const bool bit = value_ >= x;
        if (!bit) {
            length_ = x;
        } else {
            value_ -= x;
            length_ -= x;
        }
        if (length_ < kLazMinLength) renormalise();
        m.saw(bit);
        return bit;
    }
    std::uint32_t raw(int bits) {
        if (bits > 19) {
            const std::uint32_t low = rawPart(16);
            return (raw(bits - 16) << 16) | low;
        }
        return rawPart(bits);
    }

  private:
    std::uint32_t rawPart(int bits) {
        length_ >>= bits;
        const std::uint32_t sym = value_ / length_;
        value_ -= length_ * sym;
        if (length_ < kLazMinLength) renormalise();
        return sym;
    }
    std::uint32_t byte() {
        if (at_ < coded_.size()) return std::uint8_t(coded_[at_++]);
        overrun = true;
        return 0;
    }
    void renormalise() {
        do {
            value_ = (value_ << 8) | byte();
        } while ((length_ <<= 8) < kLazMinLength);
    }
    std::string_view coded_;
    std::size_t at_ = 0;
    std::uint32_t value_ = 0, length_ = 0xFFFFFFFFu;
};

class IntegerDecoder {
  public:
    explicit IntegerDecoder(int contexts) {
        for (int c = 0; c < contexts; ++c) k_models_.emplace_back(33);
        for (int k = 1; k <= 32; ++k) low_models_.emplace_back(1u << std::min(k, 8));
    }
    std::int32_t decode(RangeDecoder& d, std::int32_t predicted, int context) {
        const std::uint32_t k = d.decode(k_models_[std::size_t(context)]);
        std::uint32_t c;
        if (k == 0) {
            c = d.decode(zero_model_) ? 1u : 0u;
        } else if (k < 32) {
            std::uint32_t at = d.decode(low_models_[k - 1]);
            if (k > 8) at = (at << (k - 8)) | d.raw(int(k - 8));
            c = at >= (1u << (k - 1)) ? at + 1u : at - ((1u << k) - 1u);
        } else {
            c = 0x80000000u;  // the smallest correction
        }
        return std::int32_t(std::uint32_t(predicted) + c);
    }

  private:
    std::vector<SymbolModel> k_models_, low_models_;
    BitModel zero_model_;
};

class Parser {
  public:
    Parser(ByteSource& source, CopcLayout& layout, std::vector<CopcFinding>& findings)
        : s_(source), l_(layout), f_(findings) {}

    bool run(CopcHierarchy mode) {
        paged_ = mode == CopcHierarchy::by_page;
        l_.file_size = s_.size();
        if (!header()) return false;
        vlrs();
        evlrs();
        infoValues();
        // By page, only the table's place: its entries are as many as the nodes, and each
        // node's chunk is then checked against its hierarchy entry alone.
        if (tablePlace() && !paged_) chunkTable();
        l_.hier_at = hier_at_;
        l_.hier_size = hier_size_;
        if (l_.info_found && hierarchies_ > 0)
            hierarchy({l_.info.root_hier_offset, l_.info.root_hier_size, CopcKey{}, true});
        return l_.info_found && hierarchy_ok_;
    }

    // One child page of a layout read by page: the same checks as when the whole
    // hierarchy is read, its further child pages listed rather than followed.
    bool childPage(const CopcPage& page) {
        paged_ = true;
        hierarchies_ = 1;
        hier_at_ = l_.hier_at;
        hier_size_ = l_.hier_size;
        hierarchy({page.offset, page.bytes, page.key, false});
        return hierarchy_ok_;
    }

  private:
    void finding(const char* rule, std::string message) { f_.push_back({rule, std::move(message)}); }

    bool header() {
        const std::uint64_t size = s_.size();
        std::string h;
        if (!fetch(s_, 0, std::min<std::uint64_t>(size, kHeaderSize), h) || h.size() < 4 ||
            h.compare(0, 4, "LASF") != 0) {
            finding("not-las", "the file does not start with 'LASF'; a COPC file is a LAS 1.4 file");
            return false;
        }
        if (h.size() < kHeaderSize) {
            finding("header-length", "the file has " + n2s(size) + " bytes, fewer than a LAS 1.4 header's 375");
            return false;
        }
        l_.header = h;
        const int major = std::uint8_t(h[24]), minor = std::uint8_t(h[25]);
        if (major != 1 || minor != 4)
            finding("minor-version",
                    "LAS version " + std::to_string(major) + "." + std::to_string(minor) + "; allowed: 1.4");
        header_size_ = le<std::uint16_t>(h, 94);
        if (header_size_ != kHeaderSize)
            finding("header-length", "header size " + n2s(header_size_) + "; allowed: 375");
        l_.data_at = le<std::uint32_t>(h, 96);
        vlr_count_ = le<std::uint32_t>(h, 100);
        const unsigned raw_format = std::uint8_t(h[104]);
        l_.format = raw_format & 0x3Fu;
        l_.record = le<std::uint16_t>(h, 105);
        if (l_.format < 6 || l_.format > 8)
            finding("point-format", "point data format " + n2s(l_.format) + "; allowed: 6, 7 or 8");
        if (l_.format >= kMinRecord.size() || l_.record < kMinRecord[l_.format]) {
            finding("point-format",
                    "point records of " + n2s(l_.record) + " bytes do not fit point format " + n2s(l_.format));
            return false;
        }
        if ((raw_format & 0x80u) == 0)
            finding("laszip-encoded",
                    "the point format byte " + n2s(raw_format) + " does not mark compressed (LAZ) data (bit 7)");
        l_.legacy_count = le<std::uint32_t>(h, 107);
        for (std::size_t r = 0; r < 5; ++r) l_.legacy_by_return[r] = le<std::uint32_t>(h, 111 + 4 * r);
        for (int k = 0; k < 3; ++k) {
            l_.scale[k] = le<double>(h, 131 + 8 * std::size_t(k));
            l_.offset[k] = le<double>(h, 155 + 8 * std::size_t(k));
            l_.max[k] = le<double>(h, 179 + 16 * std::size_t(k));
            l_.min[k] = le<double>(h, 187 + 16 * std::size_t(k));
        }
        for (int k = 0; k < 3; ++k)
            if (!std::isfinite(l_.scale[k]) || l_.scale[k] <= 0.0 || !std::isfinite(l_.offset[k])) {
                finding("header-scale",
                        std::string("the scale and offset of ") + "xyz"[k] + " must be finite and the scale positive");
                return false;
            }
        evlr_at_ = le<std::uint64_t>(h, 235);
        evlr_count_ = le<std::uint32_t>(h, 243);
        l_.count = le<std::uint64_t>(h, 247);
        for (std::size_t r = 0; r < 15; ++r) l_.by_return[r] = le<std::uint64_t>(h, 255 + 8 * r);
        if (l_.data_at < header_size_ || l_.data_at > size) {
            finding("offsets", "the point data offset " + n2s(l_.data_at) + " is outside " + n2s(header_size_) +
                                   " to the file's " + n2s(size) + " bytes");
            return false;
        }
        return true;
    }

    void vlrs() {
        std::uint64_t at = header_size_;
        int infos = 0, laszips = 0;
        for (std::uint32_t v = 0; v < vlr_count_; ++v) {
            std::string vh;
            if (l_.data_at - at < kVlrHeader || !fetch(s_, at, kVlrHeader, vh)) {
                finding("vlr-count", "VLR " + n2s(v) + " of the header's " + n2s(vlr_count_) +
                                         " runs into the point data at byte " + n2s(l_.data_at));
                return;
            }
            const std::uint16_t length = le<std::uint16_t>(vh, 20);
            if (l_.data_at - at - kVlrHeader < length) {
                finding("vlr-count", "VLR " + n2s(v) + " at byte " + n2s(at) + " declares " + n2s(length) +
                                         " bytes that run into the point data at byte " + n2s(l_.data_at));
                return;
            }
            const std::string user = userId(vh);
            const std::uint16_t record = le<std::uint16_t>(vh, 18);
            std::string payload;
            fetch(s_, at + kVlrHeader, length, payload);
            if (user == "copc" && record == 1) {
                ++infos;
                if (at != kHeaderSize)
                    finding("copc-info", "the info VLR is VLR " + n2s(v) + " at byte " + n2s(at) +
                                             "; allowed: the first VLR, at byte 375");
                if (length != kInfoSize)
                    finding("copc-info", "the info VLR holds " + n2s(length) + " bytes; allowed: 160");
                else if (infos == 1)
                    info(payload);
            } else if (user == "copc" && record == 1000) {
                foundHierarchy(at + kVlrHeader, length);
            } else if (user == "laszip encoded" && record == 22204) {
                if (++laszips == 1) l_.laszip_vlr = vh + payload;
            } else if (user == "LASF_Spec" && record == 4) {
                l_.extra_vlr = vh + payload;
            }
            at += kVlrHeader + length;
        }
        if (infos == 0) finding("copc-info", "no info VLR (user \"copc\", record 1); a COPC file needs one");
        if (infos > 1) finding("copc-info", n2s(infos) + " info VLRs; allowed: exactly one");
        if (laszips != 1) {
            finding("laszip-encoded", n2s(laszips) +
                                          " LASzip VLRs (user \"laszip encoded\", record 22204); "
                                          "allowed: exactly one");
            if (laszips == 0) return;
        }
        const std::string p = l_.laszip_vlr.substr(kVlrHeader);
        if (p.size() < 34) {
            finding("laszip-encoded", "the LASzip VLR holds " + n2s(p.size()) + " bytes, fewer than 34");
            l_.laszip_vlr.clear();
            return;
        }
        const unsigned compressor = le<std::uint16_t>(p, 0);
        const std::uint32_t chunk = le<std::uint32_t>(p, 12);
        if (compressor != 3)
            finding("laszip-encoded",
                    "the LASzip compressor is " + n2s(compressor) + "; allowed: 3 (layered chunks of LAS 1.4 points)");
        if (chunk != kVariableChunks)
            finding("laszip-encoded",
                    "the LASzip chunk size is " + n2s(chunk) + "; allowed: 4294967295 (variable chunks, one per node)");
    }

    void info(const std::string& p) {
        l_.info_found = true;
        CopcInfo& i = l_.info;
        for (int k = 0; k < 3; ++k) i.center_m[std::size_t(k)] = le<double>(p, 8 * std::size_t(k));
        i.halfsize_m = le<double>(p, 24);
        i.spacing_m = le<double>(p, 32);
        i.root_hier_offset = le<std::uint64_t>(p, 40);
        i.root_hier_size = le<std::uint64_t>(p, 48);
        i.gpstime_minimum = le<double>(p, 56);
        i.gpstime_maximum = le<double>(p, 64);
        for (std::size_t r = 0; r < 11; ++r)
            if (le<std::uint64_t>(p, 72 + 8 * r) != 0)
                finding("info-reserved", "reserved word " + n2s(r) + " of the info VLR is " +
                                             n2s(le<std::uint64_t>(p, 72 + 8 * r)) + "; allowed: 0");
    }

    void foundHierarchy(std::uint64_t at, std::uint64_t length) {
        if (++hierarchies_ == 1) {
            hier_at_ = at;
            hier_size_ = length;
        }
    }

    void evlrs() {
        const std::uint64_t size = s_.size();
        if (evlr_count_ > 0) {
            std::uint64_t at = evlr_at_;
            for (std::uint32_t e = 0; e < evlr_count_; ++e) {
                std::string eh;
                if (at < l_.data_at || !fetch(s_, at, kEvlrHeader, eh)) {
                    finding("offsets", "EVLR " + n2s(e) + " of " + n2s(evlr_count_) + " at byte " + n2s(at) +
                                           " is not inside the file after the point data");
                    break;
                }
                const std::uint64_t length = le<std::uint64_t>(eh, 20);
                if (length > size - at - kEvlrHeader) {
                    finding("offsets", "EVLR " + n2s(e) + " at byte " + n2s(at) + " declares " + n2s(length) +
                                           " bytes but " + n2s(size - at - kEvlrHeader) + " follow it");
                    break;
                }
                if (userId(eh) == "copc" && le<std::uint16_t>(eh, 18) == 1000) foundHierarchy(at + kEvlrHeader, length);
                at += kEvlrHeader + length;
            }
        }
        if (hierarchies_ != 1)
            finding("copc-hierarchy", n2s(hierarchies_) +
                                          " hierarchy EVLRs (user \"copc\", record 1000); "
                                          "allowed: exactly one");
    }

    void infoValues() {
        if (!l_.info_found) return;
        const CopcInfo& i = l_.info;
        if (!std::isfinite(i.center_m[0]) || !std::isfinite(i.center_m[1]) || !std::isfinite(i.center_m[2]))
            finding("info-values", "the info VLR's centre is not finite");
        if (!(std::isfinite(i.halfsize_m) && i.halfsize_m > 0.0))
            finding("info-values", "the info VLR's halfsize " + num(i.halfsize_m) + "; allowed: finite and > 0");
        else
            for (int k = 0; k < 3; ++k)
                if (std::isfinite(i.center_m[std::size_t(k)]) &&
                    !(std::abs(i.center_m[std::size_t(k)]) + i.halfsize_m <= core::kMaxWorldCoordinate_m)) {
                    finding("info-values", std::string("the info VLR's cube reaches ") + "xyz"[k] + " = " +
                                               num(i.center_m[std::size_t(k)]) + " +- " + num(i.halfsize_m) +
                                               "; allowed: |centre| + halfsize <= " + num(core::kMaxWorldCoordinate_m) +
                                               " m (world coordinates)");
                    break;
                }
        if (!(std::isfinite(i.spacing_m) && i.spacing_m > 0.0))
            finding("info-values", "the info VLR's spacing " + num(i.spacing_m) + "; allowed: finite and > 0");
        if (!(std::isfinite(i.gpstime_minimum) && std::isfinite(i.gpstime_maximum) &&
              i.gpstime_minimum <= i.gpstime_maximum))
            finding("info-values", "the info VLR's GPS time range " + num(i.gpstime_minimum) + " to " +
                                       num(i.gpstime_maximum) + " is not finite and ordered");
        // The cube must hold the header's bounds (one scale unit of slack for rounding);
        // a cube that is not usable has its own finding above.
        if (!cubeUsable(i)) return;
        for (int k = 0; k < 3; ++k) {
            const double lo = i.center_m[std::size_t(k)] - i.halfsize_m - l_.scale[k];
            const double hi = i.center_m[std::size_t(k)] + i.halfsize_m + l_.scale[k];
            if (!(l_.min[k] >= lo && l_.max[k] <= hi))
                finding("bounds-within-cube", std::string("the header's ") + "xyz"[k] + " bounds " + num(l_.min[k]) +
                                                  " to " + num(l_.max[k]) + " are not inside the cube's " +
                                                  num(i.center_m[std::size_t(k)] - i.halfsize_m) + " to " +
                                                  num(i.center_m[std::size_t(k)] + i.halfsize_m));
        }
    }

    // The 8 bytes after the VLRs give the chunk table's place (-1: in the file's last 8
    // bytes): the chunks end there.
    bool tablePlace() {
        const std::uint64_t size = s_.size();
        const std::uint64_t first = l_.data_at + 8;
        std::string b;
        if (!fetch(s_, l_.data_at, 8, b)) {
            finding("chunk-table",
                    "the chunk table's position (8 bytes at byte " + n2s(l_.data_at) + ") is outside the file");
            return false;
        }
        std::int64_t table = le<std::int64_t>(b, 0);
        if (table == -1 && size >= 8 && fetch(s_, size - 8, 8, b)) table = le<std::int64_t>(b, 0);
        if (table < std::int64_t(first) || std::uint64_t(table) > size - std::min<std::uint64_t>(size, 8)) {
            finding("chunk-table", "the chunk table's position " + std::to_string(table) + " is outside " + n2s(first) +
                                       " to " + n2s(size >= 8 ? size - 8 : 0));
            return false;
        }
        l_.table_at = std::uint64_t(table);
        return true;
    }

    // The table lists each chunk's points and bytes, the chunks following one another
    // from the byte after the 8 that give the table's place.
    void chunkTable() {
        const std::uint64_t size = s_.size();
        const std::uint64_t first = l_.data_at + 8;
        std::string b;
        fetch(s_, l_.table_at, 8, b);
        const std::uint32_t version = le<std::uint32_t>(b, 0), n = le<std::uint32_t>(b, 4);
        if (version != 0) {
            finding("chunk-table", "the chunk table's version is " + n2s(version) + "; allowed: 0");
            return;
        }
        // Every chunk holds at least its raw first point and its point count.
        const std::uint64_t span = l_.table_at - first, most = span / (l_.record + 4);
        if (n == 0 || n > most) {
            finding("chunk-table", "the chunk table lists " + n2s(n) + " chunks; allowed: 1 to " + n2s(most) +
                                       " in the " + n2s(span) + " bytes of chunks");
            return;
        }
        // The coded table ends where the EVLRs begin, or with the file (or its last 8
        // bytes when they give the table's place).
        std::uint64_t end = size;
        if (evlr_count_ > 0 && evlr_at_ > l_.table_at && evlr_at_ <= size) end = evlr_at_;
        // A chunk's two integers take well under 20 bytes of code, however the models stand.
        const std::uint64_t coded_at = l_.table_at + 8;
        const std::uint64_t coded_bytes = std::min<std::uint64_t>(end > coded_at ? end - coded_at : 0, 20 * n + 64);
        std::string coded;
        fetch(s_, coded_at, std::size_t(coded_bytes), coded);
        RangeDecoder d(coded);
        IntegerDecoder ic(2);
        std::int32_t points = 0, bytes = 0;
        std::uint64_t at = first;
        l_.chunks.reserve(n);
        for (std::uint32_t c = 0; c < n && !d.overrun; ++c) {
            points = ic.decode(d, points, 0);
            bytes = ic.decode(d, bytes, 1);
            if (points <= 0 || bytes <= 0) {
                finding("chunk-table", "chunk " + n2s(c) + " of the table has " + std::to_string(points) +
                                           " points and " + std::to_string(bytes) + " bytes; allowed: > 0 each");
                l_.chunks.clear();
                return;
            }
            l_.chunks.push_back({at, std::uint64_t(bytes), std::uint64_t(points)});
            at += std::uint64_t(bytes);
        }
        if (d.overrun) {
            finding("chunk-table",
                    "the coded chunk table is cut short (" + n2s(coded.size()) + " bytes for " + n2s(n) + " chunks)");
            l_.chunks.clear();
            return;
        }
        if (at != l_.table_at)
            finding("chunk-table", "the table's " + n2s(n) + " chunks end at byte " + n2s(at) +
                                       " but the chunk table starts at byte " + n2s(l_.table_at));
        l_.table_found = true;
    }

    struct Page {
        std::uint64_t at, size;
        CopcKey root;
        bool top;
    };

    // Every page from `first` on: inside the hierarchy record, a whole number of
    // entries, not overlapping another; then every entry's key and what it points to. By
    // page, the child pages are listed (l_.pages) rather than read, and the rules that
    // need the whole tree (parents, dead space, chunks and points counted) are left out.
    void hierarchy(const Page& first) {
        std::deque<Page> todo{first};
        std::map<std::uint64_t, std::uint64_t> pages;  // start -> end of every page read
        std::map<CopcKey, int> keys;                   // key -> its entry's point count
        std::set<CopcKey> page_keys;                   // keys of entries that point to a child page
        std::vector<CopcNode> nodes;
        std::map<std::uint64_t, std::size_t> chunk_at;  // chunk offset -> index in l_.chunks
        for (std::size_t c = 0; c < l_.chunks.size(); ++c) chunk_at[l_.chunks[c].offset] = c;
        std::vector<bool> used(l_.chunks.size(), false);
        hierarchy_ok_ = true;
        while (!todo.empty()) {
            const Page p = todo.front();
            todo.pop_front();
            const std::string where = p.top ? std::string("the root hierarchy page") : "the page of " + keyName(p.root);
            if (p.size == 0 || p.size % kEntrySize != 0) {
                finding("hierarchy-page", where + " at byte " + n2s(p.at) + " has " + n2s(p.size) +
                                              " bytes; allowed: a positive multiple of 32");
                hierarchy_ok_ = false;
                continue;
            }
            if (p.at < hier_at_ || p.at > hier_at_ + hier_size_ || p.size > hier_at_ + hier_size_ - p.at) {
                finding("hierarchy-page", where + " (bytes " + n2s(p.at) + " to " + n2s(p.at + p.size) +
                                              ") is not inside the hierarchy EVLR's bytes " + n2s(hier_at_) + " to " +
                                              n2s(hier_at_ + hier_size_));
                hierarchy_ok_ = false;
                continue;
            }
            if (l_.page_entries_max > 0 && p.size / kEntrySize > l_.page_entries_max) {
                finding("hierarchy-page", where + " has " + n2s(p.size / kEntrySize) + " entries; allowed at most " +
                                              n2s(l_.page_entries_max) + " in one page (" + l_.page_bound_source + ")");
                hierarchy_ok_ = false;
                continue;
            }
            const auto next = pages.lower_bound(p.at);
            const bool overlaps = (next != pages.end() && next->first < p.at + p.size) ||
                                  (next != pages.begin() && std::prev(next)->second > p.at);
            if (overlaps) {
                finding("hierarchy-page", where + " (bytes " + n2s(p.at) + " to " + n2s(p.at + p.size) +
                                              ") overlaps a page already read");
                hierarchy_ok_ = false;
                continue;
            }
            pages[p.at] = p.at + p.size;
            std::string page;
            fetch(s_, p.at, std::size_t(p.size), page);
            for (std::size_t e = 0; e < page.size(); e += kEntrySize) {
                const CopcKey key{le<std::int32_t>(page, e), le<std::int32_t>(page, e + 4),
                                  le<std::int32_t>(page, e + 8), le<std::int32_t>(page, e + 12)};
                const std::uint64_t offset = le<std::uint64_t>(page, e + 16);
                const std::int32_t bytes = le<std::int32_t>(page, e + 24);
                const std::int32_t count = le<std::int32_t>(page, e + 28);
                const std::string name = "node " + keyName(key);
                if (!validKey(key)) {
                    finding("node-key", name + " (in " + where +
                                            "): allowed: level 0 to 30 and x, y, z in 0 to "
                                            "2^level - 1");
                    hierarchy_ok_ = false;
                    continue;
                }
                if (!p.top && !within(key, p.root))
                    finding("node-key", name + " is in " + where + " but is not " + keyName(p.root) + " or below it");
                if (count == -1) {
                    if (!page_keys.insert(key).second) finding("node-key", name + " points to a child page twice");
                    if (paged_ && !p.top && key == p.root) {
                        // Read whole, the page would overlap itself; by page, say so here.
                        finding("hierarchy-page", where + " points to a child page for its own key");
                        hierarchy_ok_ = false;
                        continue;
                    }
                    if (bytes <= 0) {
                        finding("hierarchy-page", "the child page of " + keyName(key) + " has " +
                                                      std::to_string(bytes) +
                                                      " bytes; allowed: a positive multiple "
                                                      "of 32");
                        hierarchy_ok_ = false;
                    } else if (paged_) {
                        l_.pages.push_back({key, offset, std::uint64_t(bytes)});
                    } else {
                        todo.push_back({offset, std::uint64_t(bytes), key, false});
                    }
                    continue;
                }
                if (count < -1) {
                    finding("hierarchy-entry", name + " has point count " + std::to_string(count) +
                                                   "; allowed: -1 (a child page), 0 or more");
                    continue;
                }
                if (!keys.emplace(key, count).second) {
                    finding("node-key", name + " has a second entry; allowed: one per node");
                    hierarchy_ok_ = false;
                    continue;
                }
                if (count == 0) {
                    if (offset != 0 || bytes != 0)
                        finding("hierarchy-entry", name + " has no points but offset " + n2s(offset) + " and " +
                                                       std::to_string(bytes) + " bytes; allowed: 0 and 0");
                    l_.empty_nodes.push_back(key);
                    continue;
                }
                if (bytes <= 0 || offset < l_.data_at + 8 || offset > s_.size() ||
                    std::uint64_t(bytes) > s_.size() - offset ||
                    (l_.table_at != 0 && offset + std::uint64_t(bytes) > l_.table_at)) {
                    finding("node-chunk", name + "'s chunk (" + std::to_string(bytes) + " bytes at byte " +
                                              n2s(offset) + ") is not inside the point data, bytes " +
                                              n2s(l_.data_at + 8) + " to " +
                                              n2s(l_.table_at ? l_.table_at : s_.size()));
                    hierarchy_ok_ = false;
                    continue;
                }
                nodes.push_back({key, offset, bytes, count});
                if (!l_.table_found) continue;
                const auto c = chunk_at.find(offset);
                if (c == chunk_at.end()) {
                    finding("node-chunk",
                            name + "'s offset " + n2s(offset) + " is not where a chunk of the chunk table starts");
                    hierarchy_ok_ = false;
                    continue;
                }
                const CopcChunk& chunk = l_.chunks[c->second];
                if (chunk.bytes != std::uint64_t(bytes) || chunk.points != std::uint64_t(count)) {
                    finding("node-chunk", name + " declares " + std::to_string(count) + " points in " +
                                              std::to_string(bytes) + " bytes but its chunk in the table has " +
                                              n2s(chunk.points) + " points in " + n2s(chunk.bytes) + " bytes");
                    hierarchy_ok_ = false;
                }
                if (used[c->second]) {
                    finding("node-chunk", name + " shares its chunk at byte " + n2s(offset) + " with another node");
                    hierarchy_ok_ = false;
                }
                used[c->second] = true;
            }
        }
        std::sort(nodes.begin(), nodes.end(), [](const CopcNode& a, const CopcNode& b) { return a.key < b.key; });
        std::sort(l_.empty_nodes.begin(), l_.empty_nodes.end());
        if (paged_) {
            l_.nodes = std::move(nodes);
            return;
        }
        wholeHierarchy(keys, page_keys, pages, used, nodes);
        l_.nodes = std::move(nodes);
    }

    // The rules over the whole hierarchy once every page is read (not by page): parents,
    // the root, dead space between pages, chunks of no node, the header's point count.
    void wholeHierarchy(const std::map<CopcKey, int>& keys, const std::set<CopcKey>& page_keys,
                        const std::map<std::uint64_t, std::uint64_t>& pages, const std::vector<bool>& used,
                        const std::vector<CopcNode>& nodes) {
        // Every node's parent has an entry (a node, an empty node or a child page's).
        for (const auto& [key, count] : keys) {
            if (key.level == 0) continue;
            const CopcKey parent{key.level - 1, key.x >> 1, key.y >> 1, key.z >> 1};
            if (!keys.count(parent) && !page_keys.count(parent))
                finding("node-key", "node " + keyName(key) + " has no parent entry (" + keyName(parent) + ")");
        }
        if (!keys.empty() && !keys.count(CopcKey{}) && !page_keys.count(CopcKey{}))
            finding("node-key", "the hierarchy has no entry for the root node 0-0-0-0");
        // No bytes of the hierarchy record belong to no page.
        std::uint64_t at = hier_at_;
        for (const auto& [start, end] : pages) {
            if (start > at)
                finding("hierarchy-dead-space", "bytes " + n2s(at) + " to " + n2s(start) +
                                                    " of the hierarchy EVLR are in no page reached from the root");
            at = std::max(at, end);
        }
        if (hier_at_ + hier_size_ > at)
            finding("hierarchy-dead-space", "bytes " + n2s(at) + " to " + n2s(hier_at_ + hier_size_) +
                                                " of the hierarchy EVLR are in no page reached from the root");
        // Every chunk belongs to a node, and the nodes hold the header's points.
        std::size_t unused = 0;
        for (std::size_t c = 0; c < used.size(); ++c)
            if (!used[c] && unused++ < 20)
                finding("chunk-unreferenced", "chunk " + n2s(c) + " of the chunk table (" + n2s(l_.chunks[c].points) +
                                                  " points at byte " + n2s(l_.chunks[c].offset) +
                                                  ") belongs to no node of the hierarchy");
        if (unused > 20) finding("chunk-unreferenced", n2s(unused - 20) + " more chunks belong to no node");
        std::uint64_t total = 0;
        for (const CopcNode& n : nodes) total += std::uint64_t(n.point_count);
        if (total != l_.count)
            finding("point-count",
                    "the hierarchy's nodes hold " + n2s(total) + " points but the header counts " + n2s(l_.count));
    }

    static bool validKey(const CopcKey& k) {
        if (k.level < 0 || k.level > kMaxLevel) return false;
        const std::int64_t cells = std::int64_t(1) << k.level;
        return k.x >= 0 && k.y >= 0 && k.z >= 0 && k.x < cells && k.y < cells && k.z < cells;
    }

    // Whether `k` is `root` or one of its descendants.
    static bool within(const CopcKey& k, const CopcKey& root) {
        if (k.level < root.level) return false;
        const int up = k.level - root.level;
        return (k.x >> up) == root.x && (k.y >> up) == root.y && (k.z >> up) == root.z;
    }

    ByteSource& s_;
    CopcLayout& l_;
    std::vector<CopcFinding>& f_;
    std::uint64_t header_size_ = 0;
    std::uint32_t vlr_count_ = 0;
    std::uint64_t evlr_at_ = 0;
    std::uint32_t evlr_count_ = 0;
    int hierarchies_ = 0;
    std::uint64_t hier_at_ = 0, hier_size_ = 0;
    bool hierarchy_ok_ = false;
    bool paged_ = false;
};

}  // namespace

bool parseCopc(ByteSource& source, CopcLayout& layout, std::vector<CopcFinding>& findings, CopcHierarchy mode) {
    return Parser(source, layout, findings).run(mode);
}

bool parseCopcPage(ByteSource& source, const CopcLayout& layout, const CopcPage& page, CopcPageEntries& entries,
                   std::vector<CopcFinding>& findings) {
    // What the page's checks read of the file's layout; its entries come back in `l`.
    CopcLayout l;
    l.file_size = layout.file_size;
    l.data_at = layout.data_at;
    l.table_at = layout.table_at;
    l.info_found = true;
    l.info = layout.info;
    l.hier_at = layout.hier_at;
    l.hier_size = layout.hier_size;
    l.page_entries_max = layout.page_entries_max;
    l.page_bound_source = layout.page_bound_source;
    const bool ok = Parser(source, l, findings).childPage(page);
    entries.nodes = std::move(l.nodes);
    entries.empty_nodes = std::move(l.empty_nodes);
    entries.pages = std::move(l.pages);
    return ok;
}

std::string keyName(const CopcKey& key) {
    return std::to_string(key.level) + "-" + std::to_string(key.x) + "-" + std::to_string(key.y) + "-" +
           std::to_string(key.z);
}

bool cubeUsable(const CopcInfo& info) {
    if (!(std::isfinite(info.halfsize_m) && info.halfsize_m > 0.0)) return false;
    for (const double c : info.center_m)
        if (!(std::abs(c) + info.halfsize_m <= core::kMaxWorldCoordinate_m)) return false;
    return true;
}

void nodeCube(const CopcInfo& info, const CopcKey& key, glm::dvec3& lo, glm::dvec3& hi) {
    const double side = 2.0 * info.halfsize_m / double(std::int64_t(1) << key.level);
    const double cell[3] = {double(key.x), double(key.y), double(key.z)};
    for (int k = 0; k < 3; ++k) {
        lo[k] = info.center_m[std::size_t(k)] - info.halfsize_m + cell[k] * side;
        hi[k] = lo[k] + side;
    }
}

void frameBounds(const CopcLayout& layout, glm::dvec3& min, glm::dvec3& max) {
    min = layout.min;
    max = layout.max;
    if (!layout.info_found || !cubeUsable(layout.info)) return;
    const CopcInfo& i = layout.info;
    bool sane = true;
    for (int k = 0; k < 3; ++k) {
        const double lo = i.center_m[std::size_t(k)] - i.halfsize_m - kFrameSlack;
        const double hi = i.center_m[std::size_t(k)] + i.halfsize_m + kFrameSlack;
        sane = sane && min[k] >= lo && min[k] <= hi && max[k] >= lo && max[k] <= hi;
    }
    if (sane) return;
    for (int k = 0; k < 3; ++k) {
        min[k] = i.center_m[std::size_t(k)] - i.halfsize_m;
        max[k] = i.center_m[std::size_t(k)] + i.halfsize_m;
    }
}

std::string nodeLaz(ByteSource& source, const CopcLayout& layout, const CopcNode& node) {
    std::string laszip = layout.laszip_vlr;
    put<std::uint32_t>(laszip, kVlrHeader + 12, std::uint32_t(node.point_count));  // one chunk of them all
    std::string out = layout.header.substr(0, kHeaderSize);
    const std::uint64_t data_at = kHeaderSize + laszip.size() + layout.extra_vlr.size();
    put<std::uint16_t>(out, 94, std::uint16_t(kHeaderSize));
    put<std::uint32_t>(out, 96, std::uint32_t(data_at));
    put<std::uint32_t>(out, 100, layout.extra_vlr.empty() ? 1u : 2u);
    put<std::uint32_t>(out, 107, 0u);  // legacy counts: zero for point formats 6 and up
    for (std::size_t r = 0; r < 5; ++r) put<std::uint32_t>(out, 111 + 4 * r, 0u);
    put<std::uint64_t>(out, 227, 0u);  // no waveform data
    put<std::uint64_t>(out, 235, 0u);  // no EVLRs
    put<std::uint32_t>(out, 243, 0u);
    put<std::uint64_t>(out, 247, std::uint64_t(node.point_count));
    for (std::size_t r = 0; r < 15; ++r) put<std::uint64_t>(out, 255 + 8 * r, 0u);
    glm::dvec3 min, max;
    frameBounds(layout, min, max);
    for (std::size_t k = 0; k < 3; ++k) {
        put<double>(out, 179 + 16 * k, max[int(k)]);
        put<double>(out, 187 + 16 * k, min[int(k)]);
    }
    out += laszip;
    out += layout.extra_vlr;
    const std::uint64_t table_at = data_at + 8 + std::uint64_t(node.byte_size);
    out.append(8, '\0');
    put<std::uint64_t>(out, std::size_t(data_at), table_at);
    out += source.view(node.offset, std::size_t(node.byte_size));
    const std::uint32_t bytes[1] = {std::uint32_t(node.byte_size)};
    out += lazChunkTable(bytes);
    return out;
}

}  // namespace io::detail
