// pcd_reader: PCD v0.7 (DATA ascii, binary, binary_compressed), read defensively: the
// whole header is checked (and the data size against the file) before the first point,
// every count is bounded by the bytes present, and nothing may follow the declared
// points but zero padding. Why our own PCD/PLY codec: docs/formats.md.
#include "cloud_decode.hpp"

#include <core/error.hpp>

#include <lzf.h>

#include <array>
#include <algorithm>
#include <cstring>
#include <limits>
#include <optional>

namespace io::detail {

using core::CloudPoint;
using core::Error;

namespace {

struct PcdHeader {
    glm::dvec3 origin{0.0};
    bool ours = false;  // the header has the ladarvr origin comment
    Layout layout;
    std::size_t points = 0;
    std::size_t record = 0;     // bytes per point (binary)
    std::size_t per_point = 0;  // values per point (ascii)
    std::size_t lines = 0;      // header lines, for messages about the data
    std::uint64_t body = 0;     // byte offset of the data
    std::string data;           // ascii, binary, binary_compressed
};

/// A header comment: "# ladarvr origin X Y Z" (also "#ladarvr origin ...") sets the
/// header's origin and marks it ours; other comments are free.
void readComment(const std::vector<std::string_view>& words, const std::string& where, PcdHeader& h) {
    if (words[0] == "#" && words.size() > 2 && words[1] == "ladarvr" && words[2] == "origin") {
        h.origin = parseOrigin(words, 3, where);
        h.ours = true;
    } else if (words[0] == "#ladarvr" && words.size() > 1 && words[1] == "origin") {
        h.origin = parseOrigin(words, 2, where);
        h.ours = true;
    }
}

/// Parses and checks the header in `text` (the first bytes of the file).
PcdHeader parseHeader(std::string_view text, std::uint64_t file_size, const std::string& pre) {
    PcdHeader h;
    LineReader lines{text};
    std::string_view line;
    std::vector<std::string> names;
    std::vector<int> sizes, counts;
    std::vector<char> types;
    std::optional<std::size_t> width, height, points_field;
    bool have_size = false, have_type = false;
    // Until the first keyword the file is not known to be a PCD (it may be any file a
    // design or option names): nothing of it is quoted in a message before then.
    bool started = false;
    while (h.data.empty()) {
        if (!lines.next(line)) {
            if (file_size > text.size()) throw Error(pre + ": the header is longer than 1 MiB; not a PCD file?");
            throw Error(pre + ": the header ends without a DATA line; not a PCD file?");
        }
        if (lines.line_no > kMaxHeaderLines) throw Error(pre + ": the header is too long; not a PCD file?");
        const auto words = splitWords(line);
        if (words.empty()) continue;
        const std::string where = pre + ": line " + std::to_string(lines.line_no);
        if (words[0].front() == '#') {
            readComment(words, where, h);
            continue;
        }
        const std::string_view key = words[0];
        const bool first_keyword = !started;
        started = true;
        auto one = [&](std::optional<std::size_t>& out) {
            out.emplace();
            if (words.size() != 2 || !parseExact(words[1], *out))
                throw Error(where + ": " + std::string(key) + " needs one non-negative integer");
        };
        if (key == "VERSION" || key == "VIEWPOINT") {
        } else if (key == "FIELDS") {
            names.clear();
            for (std::size_t k = 1; k < words.size(); ++k) names.emplace_back(words[k]);
            if (names.empty()) throw Error(where + ": FIELDS lists no field");
        } else if (key == "SIZE") {
            have_size = true;
            sizes.clear();
            for (std::size_t k = 1; k < words.size(); ++k) {
                int s = 0;
                if (!parseExact(words[k], s) || (s != 1 && s != 2 && s != 4 && s != 8))
                    throw Error(where + ": SIZE '" + core::printable(words[k], 20) + "' is not one of 1, 2, 4, 8");
                sizes.push_back(s);
            }
        } else if (key == "TYPE") {
            have_type = true;
            types.clear();
            for (std::size_t k = 1; k < words.size(); ++k) {
                if (words[k] != "F" && words[k] != "U" && words[k] != "I")
                    throw Error(where + ": TYPE '" + core::printable(words[k], 20) + "' is not one of F, U, I");
                types.push_back(words[k][0]);
            }
        } else if (key == "COUNT") {
            counts.clear();
            for (std::size_t k = 1; k < words.size(); ++k) {
                int c = 0;
                if (!parseExact(words[k], c) || c < 1 || c > 1000000)
                    throw Error(where + ": COUNT '" + core::printable(words[k], 20) +
                                "' is not an integer in 1..1000000");
                counts.push_back(c);
            }
        } else if (key == "WIDTH") {
            one(width);
        } else if (key == "HEIGHT") {
            one(height);
        } else if (key == "POINTS") {
            one(points_field);
        } else if (key == "DATA") {
            if (words.size() != 2 || (words[1] != "ascii" && words[1] != "binary" && words[1] != "binary_compressed"))
                throw Error(where + ": DATA must be one of ascii, binary, binary_compressed");
            h.data = std::string(words[1]);
        } else {
            if (first_keyword)
                throw Error(where +
                            ": not a PCD file (a PCD header starts with '#' comments and keywords such as "
                            "VERSION or FIELDS)");
            throw Error(where + ": unknown header keyword '" + core::printable(key, 20) +
                        "'; allowed: VERSION, FIELDS, SIZE, TYPE, COUNT, WIDTH, HEIGHT, "
                        "VIEWPOINT, POINTS, DATA");
        }
    }
    h.lines = lines.line_no;
    h.body = lines.pos;
    if (names.empty()) throw Error(pre + ": the header has no FIELDS line");
    if (!have_size || sizes.size() != names.size())
        throw Error(pre + ": SIZE has " + std::to_string(sizes.size()) + " entries but FIELDS has " +
                    std::to_string(names.size()));
    if (!have_type || types.size() != names.size())
        throw Error(pre + ": TYPE has " + std::to_string(types.size()) + " entries but FIELDS has " +
                    std::to_string(names.size()));
    if (counts.empty()) counts.assign(names.size(), 1);
    if (counts.size() != names.size())
        throw Error(pre + ": COUNT has " + std::to_string(counts.size()) + " entries but FIELDS has " +
                    std::to_string(names.size()));
    if (!width) throw Error(pre + ": the header has no WIDTH line");
    if (!height) height = 1;
    if (*height != 0 && *width > std::numeric_limits<std::size_t>::max() / *height)
        throw Error(pre + ": WIDTH x HEIGHT overflows");
    h.points = *width * *height;
    if (points_field && *points_field != h.points)
        throw Error(pre + ": POINTS " + std::to_string(*points_field) +
                    " is not WIDTH x HEIGHT = " + std::to_string(h.points));

    Layout& l = h.layout;
    std::size_t offset = 0, token = 0;
    for (std::size_t f = 0; f < names.size(); ++f) {
        const char t = types[f];
        const int s = sizes[f];
        if (t == 'F' && s != 4 && s != 8)
            throw Error(pre + ": field '" + core::printable(names[f], 40) + "': TYPE F needs SIZE 4 or 8, not " +
                        std::to_string(s));
        Column c;
        c.present = true;
        c.type = {t == 'F' ? Kind::Float : t == 'U' ? Kind::UInt : Kind::Int, s};
        c.base = offset;
        c.token = token;
        const std::string& nm = names[f];
        Column* slot = nullptr;
        if (nm == "x")
            slot = &l.x;
        else if (nm == "y")
            slot = &l.y;
        else if (nm == "z")
            slot = &l.z;
        else if (nm == "rgb" || nm == "rgba")
            slot = &l.rgb;
        else
            slot = columnFor(l, nm);
        // What the label's codes mean: ours, ASPRS classes, or both (LabelCodes).
        if (slot == &l.label && !l.label.present) l.label_codes = labelCodesFor(nm, h.ours);
        if (slot && counts[f] != 1)
            throw Error(pre + ": field '" + core::printable(nm, 40) + "' has COUNT " + std::to_string(counts[f]) +
                        "; allowed: 1");
        if (slot == &l.rgb && s != 4)
            throw Error(pre + ": field '" + core::printable(nm, 40) + "' has SIZE " + std::to_string(s) +
                        "; allowed: 4");
        if (slot && !slot->present) *slot = c;
        offset += std::size_t(s) * std::size_t(counts[f]);
        token += std::size_t(counts[f]);
    }
    if (!l.x.present || !l.y.present || !l.z.present)
        throw Error(pre + ": FIELDS has no x, y and z; they are required");
    l.rgb_float_text = l.rgb.present && l.rgb.type.kind == Kind::Float;
    h.record = offset;
    h.per_point = token;
    return h;
}

class PcdReader final : public FormatReader {
  public:
    PcdReader(ByteSource& source, const std::string& prefix)
        : source_(source),
          prefix_(prefix),
          h_(parseHeader(headerPrefix(source), source.size(), prefix)),
          tokens_(source, h_.body, prefix) {
        origin = h_.origin;
        fields = h_.layout.fields();
        declared = h_.points;
        const std::uint64_t remaining = source.size() - h_.body;
        // Text takes at least 2 bytes per value; binary sizes are checked below.
        bound = std::min<std::uint64_t>(h_.points, remaining / (2 * h_.per_point) + 1);
        if (h_.data == "binary") {
            if (h_.points > remaining / h_.record)
                throw Error(prefix_ + ": truncated: the header says " + std::to_string(h_.points) + " points of " +
                            std::to_string(h_.record) + " bytes but only " + std::to_string(remaining) +
                            " bytes of data follow the header");
            checkPadding(source, h_.body + h_.points * h_.record, prefix_,
                         std::to_string(h_.points) + " points the header declares");
            for (Column* c : columns()) c->stride = h_.record;
            bound = h_.points;
        } else if (h_.data == "binary_compressed") {
            decompress(remaining);
            bound = h_.points;
        }
        shiftOrigin();
    }

    std::size_t next(std::vector<CloudPoint>& out, std::size_t max_points) override {
        const std::size_t n = std::min(max_points, h_.points - done_);
        if (n == 0) {
            if (h_.data == "ascii" && !end_checked_) {
                end_checked_ = true;
                std::string_view extra;
                if (tokens_.next(extra))
                    throw Error(prefix_ + ": line " + std::to_string(h_.lines + tokens_.lineNo()) +
                                ": data follow the " + std::to_string(h_.points) +
                                " points the header declares; the header must count every point");
            }
            return 0;
        }
        if (h_.data == "ascii") {
            decodeText(tokens_, n, h_.per_point, h_.layout, done_, h_.points, h_.lines, prefix_, out, stats);
        } else if (h_.data == "binary") {
            const std::string_view bytes = source_.view(h_.body + done_ * h_.record, n * h_.record);
            decodeBinary(reinterpret_cast<const unsigned char*>(bytes.data()), 0, n, h_.layout, false, done_, prefix_,
                         out, stats);
        } else {
            decodeBinary(plain_.data(), done_, n, h_.layout, false, done_, prefix_, out, stats);
        }
        done_ += n;
        return n;
    }

  private:
    std::array<Column*, 13> columns() {
        Layout& l = h_.layout;
        return {&l.x,
                &l.y,
                &l.z,
                &l.rgb,
                &l.label,
                &l.view,
                &l.range,
                &l.intensity,
                &l.return_number,
                &l.returns,
                &l.incidence,
                &l.scan_angle,
                &l.height_above_ground};
    }

    // Georeferenced coordinates: double (or integer) columns move onto a double origin
    // taken from the first point before the cast to float.
    void shiftOrigin() {
        if (h_.points == 0 || !h_.layout.wideXyz()) return;
        glm::dvec3 first{0.0};
        if (h_.data == "ascii") {
            TextStream peek(source_, h_.body, prefix_);
            if (!peekTextXyz(peek, h_.layout, h_.per_point, first)) return;
        } else {
            const unsigned char* base =
                h_.data == "binary" ? reinterpret_cast<const unsigned char*>(source_.view(h_.body, h_.record).data())
                                    : plain_.data();
            first = peekBinaryXyz(base, h_.layout, false);  // column bases are point 0's
        }
        h_.layout.shift = shiftFor(first);
        origin += h_.layout.shift;
    }

    // binary_compressed: the sizes (compressed, uncompressed) then one LZF block holding
    // each field for all points in turn. The block is decompressed here, once; its size
    // must be the header's points x record and is bounded by LZF's ratio to the bytes
    // actually present.
    void decompress(std::uint64_t remaining) {
        if (remaining < 8) throw Error(prefix_ + ": truncated: binary_compressed data need an 8-byte size header");
        const std::string_view sizes = source_.view(h_.body, 8);
        std::uint32_t packed = 0, unpacked = 0;
        std::memcpy(&packed, sizes.data(), 4);
        std::memcpy(&unpacked, sizes.data() + 4, 4);
        if (packed > remaining - 8)
            throw Error(prefix_ + ": truncated: the compressed block is " + std::to_string(packed) +
                        " bytes but only " + std::to_string(remaining - 8) + " follow");
        const std::size_t n = h_.points, record = h_.record;
        if (n > std::numeric_limits<std::uint32_t>::max() / record || unpacked != n * record)
            throw Error(prefix_ + ": binary_compressed: the uncompressed size " + std::to_string(unpacked) +
                        " is not points x record size = " + std::to_string(n) + " x " + std::to_string(record));
        // LZF expands at most ~90x; a larger claim is corrupt (and would allocate a lot).
        if (unpacked > std::size_t(packed) * 100 + 64)
            throw Error(prefix_ + ": binary_compressed: the uncompressed size " + std::to_string(unpacked) +
                        " is impossible for " + std::to_string(packed) + " compressed bytes");
        checkPadding(source_, h_.body + 8 + packed, prefix_, "compressed block");
        plain_.resize(unpacked);
        if (unpacked > 0) {
            const std::string_view block = source_.view(h_.body + 8, packed);
            // liblzf checks every back reference and both buffer ends (CHECK_INPUT); the
            // result must fill exactly the size the header implies.
            const unsigned int got = lzf_decompress(block.data(), unsigned(packed), plain_.data(), unpacked);
            if (got != unpacked) throw Error(prefix_ + ": binary_compressed: the LZF data are corrupt");
        }
        for (Column* c : columns()) {
            c->stride = std::size_t(c->type.size);
            c->base *= n;
        }
    }

    ByteSource& source_;
    std::string prefix_;
    PcdHeader h_;
    TextStream tokens_;
    std::vector<unsigned char> plain_;
    std::size_t done_ = 0;
    bool end_checked_ = false;
};

}  // namespace

std::unique_ptr<FormatReader> openPcd(ByteSource& source, const std::string& prefix) {
    return std::make_unique<PcdReader>(source, prefix);
}

}  // namespace io::detail
