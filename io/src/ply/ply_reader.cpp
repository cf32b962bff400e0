// ply_reader: PLY 1.0 (ascii, binary_little_endian, binary_big_endian), read
// defensively: the header and the elements before the vertices are checked before the
// first point, every count is bounded by the bytes present, and when the vertices are
// the last element nothing may follow them but zero padding. Why our own PCD/PLY codec:
// docs/formats.md.
#include "cloud_decode.hpp"

#include <core/error.hpp>

#include <algorithm>
#include <cstring>
#include <optional>

namespace io::detail {

using core::CloudPoint;
using core::Error;

namespace {

struct PlyProperty {
    std::string name;
    ScalarType type;
    bool is_list = false;
    ScalarType count_type;
};

struct PlyElement {
    std::string name;
    std::size_t count = 0;
    std::vector<PlyProperty> props;
};

bool plyType(std::string_view s, ScalarType& t) {
    if (s == "char" || s == "int8")
        t = {Kind::Int, 1};
    else if (s == "uchar" || s == "uint8")
        t = {Kind::UInt, 1};
    else if (s == "short" || s == "int16")
        t = {Kind::Int, 2};
    else if (s == "ushort" || s == "uint16")
        t = {Kind::UInt, 2};
    else if (s == "int" || s == "int32")
        t = {Kind::Int, 4};
    else if (s == "uint" || s == "uint32")
        t = {Kind::UInt, 4};
    else if (s == "float" || s == "float32")
        t = {Kind::Float, 4};
    else if (s == "double" || s == "float64")
        t = {Kind::Float, 8};
    else
        return false;
    return true;
}

/// A list count of `t` at `p`, as an unsigned integer; false if negative or absurd.
bool listCount(const unsigned char* p, ScalarType t, bool swap, std::size_t& out) {
    unsigned char b[8];
    std::memcpy(b, p, std::size_t(t.size));
    if (swap) std::reverse(b, b + t.size);
    std::int64_t v = 0;
    switch (t.size) {
        case 1: v = t.kind == Kind::Int ? std::int64_t(std::int8_t(b[0])) : std::int64_t(b[0]); break;
        case 2: {
            std::uint16_t u;
            std::memcpy(&u, b, 2);
            v = t.kind == Kind::Int ? std::int64_t(std::int16_t(u)) : std::int64_t(u);
            break;
        }
        default: {
            std::uint32_t u;
            std::memcpy(&u, b, 4);
            v = t.kind == Kind::Int ? std::int64_t(std::int32_t(u)) : std::int64_t(u);
            break;
        }
    }
    if (v < 0) return false;
    out = std::size_t(v);
    return true;
}

class PlyReader final : public FormatReader {
  public:
    PlyReader(ByteSource& source, const std::string& prefix) : source_(source), prefix_(prefix) {
        parseHeader(headerPrefix(source));
        declared = elements_[vi_].count;
        if (format_ == "ascii") {
            // Georeferenced coordinates: moved onto a double origin taken from the first
            // vertex before the cast to float. A stream of its own finds that vertex.
            tokens_.emplace(source, body_, prefix);
            skipTextElements();
            glm::dvec3 first{0.0};
            if (declared > 0 && layout_.wideXyz() && peekTextXyz(*tokens_, layout_, elements_[vi_].props.size(), first))
                layout_.shift = shiftFor(first);
            tokens_.emplace(source, body_, prefix);
            skipTextElements();
            bound = std::min<std::uint64_t>(declared, (source.size() - body_) / (2 * elements_[vi_].props.size()) + 1);
        } else {
            tokens_.emplace(source, body_, prefix);
            skipBinaryElements();
            bound = declared;
            if (declared > 0 && layout_.wideXyz()) {
                const std::string_view first = source_.view(vertex_at_, record_);
                layout_.shift = shiftFor(peekBinaryXyz(reinterpret_cast<const unsigned char*>(first.data()), layout_,
                                                       format_ == "binary_big_endian"));
            }
        }
        origin += layout_.shift;
    }

    std::size_t next(std::vector<CloudPoint>& out, std::size_t max_points) override {
        const std::size_t n = std::min(max_points, declared - done_);
        if (n == 0) {
            if (format_ == "ascii" && last_ && !end_checked_) {
                end_checked_ = true;
                std::string_view extra;
                if (tokens_->next(extra))
                    throw Error(prefix_ + ": line " + std::to_string(lines_ + tokens_->lineNo()) +
                                ": data follow the " + std::to_string(declared) +
                                " vertices the header declares; the header must count every point");
            }
            return 0;
        }
        if (format_ == "ascii") {
            decodeText(*tokens_, n, elements_[vi_].props.size(), layout_, done_, declared, lines_, prefix_, out, stats);
        } else {
            const std::string_view bytes = source_.view(vertex_at_ + done_ * record_, n * record_);
            decodeBinary(reinterpret_cast<const unsigned char*>(bytes.data()), 0, n, layout_,
                         format_ == "binary_big_endian", done_, prefix_, out, stats);
        }
        done_ += n;
        return n;
    }

  private:
    void parseHeader(const std::string& text) {
        const std::string& pre = prefix_;
        LineReader lines{text};
        std::string_view line;
        lines.next(line);
        if (splitWords(line) != std::vector<std::string_view>{"ply"})
            throw Error(pre + ": line 1: not a PLY file (a PLY file starts with the line 'ply')");
        bool ended = false;
        const char* kTypes = "char, uchar, short, ushort, int, uint, float, double";
        while (!ended) {
            if (!lines.next(line)) {
                if (source_.size() > text.size())
                    throw Error(pre + ": the header is longer than 1 MiB; not a PLY file?");
                throw Error(pre + ": the header ends without 'end_header'");
            }
            if (lines.line_no > kMaxHeaderLines) throw Error(pre + ": the header is too long; not a PLY file?");
            const auto words = splitWords(line);
            if (words.empty()) continue;
            const std::string where = pre + ": line " + std::to_string(lines.line_no);
            const std::string_view key = words[0];
            if (key == "format") {
                if (words.size() != 3 ||
                    (words[1] != "ascii" && words[1] != "binary_little_endian" && words[1] != "binary_big_endian"))
                    throw Error(where +
                                ": format must be one of ascii, binary_little_endian, "
                                "binary_big_endian (version 1.0)");
                format_ = std::string(words[1]);
            } else if (key == "comment") {
                if (words.size() > 2 && words[1] == "ladarvr" && words[2] == "origin") {
                    origin = parseOrigin(words, 3, where);
                    ours = true;
                }
            } else if (key == "obj_info") {
            } else if (key == "element") {
                PlyElement e;
                if (words.size() != 3 || !parseExact(words[2], e.count))
                    throw Error(where + ": 'element' needs a name and a non-negative count");
                e.name = std::string(words[1]);
                elements_.push_back(std::move(e));
            } else if (key == "property") {
                if (elements_.empty()) throw Error(where + ": 'property' before any 'element'");
                PlyProperty p;
                if (words.size() == 5 && words[1] == "list") {
                    p.is_list = true;
                    if (!plyType(words[2], p.count_type) || p.count_type.kind == Kind::Float || p.count_type.size > 4 ||
                        !plyType(words[3], p.type))
                        throw Error(where +
                                    ": list property types must be an integer count type and "
                                    "one of " +
                                    kTypes);
                    p.name = std::string(words[4]);
                } else if (words.size() == 3) {
                    if (!plyType(words[1], p.type))
                        throw Error(where + ": property type '" + core::printable(words[1], 20) + "' is not one of " +
                                    kTypes);
                    p.name = std::string(words[2]);
                } else {
                    throw Error(where + ": 'property' needs a type and a name");
                }
                elements_.back().props.push_back(std::move(p));
            } else if (key == "end_header") {
                ended = true;
            } else {
                throw Error(where + ": unknown header keyword '" + core::printable(key, 20) +
                            "'; allowed: format, comment, obj_info, element, property, end_header");
            }
        }
        if (format_.empty()) throw Error(pre + ": the header has no 'format' line");
        lines_ = lines.line_no;
        body_ = lines.pos;
        vi_ = elements_.size();
        for (std::size_t e = 0; e < elements_.size(); ++e)
            if (elements_[e].name == "vertex") {
                vi_ = e;
                break;
            }
        if (vi_ == elements_.size()) throw Error(pre + ": the header has no 'element vertex'");
        last_ = true;
        for (std::size_t e = vi_ + 1; e < elements_.size(); ++e)
            if (elements_[e].count > 0 && !elements_[e].props.empty()) last_ = false;

        const PlyElement& vertex = elements_[vi_];
        Layout& l = layout_;
        std::size_t offset = 0;
        for (std::size_t k = 0; k < vertex.props.size(); ++k) {
            const PlyProperty& p = vertex.props[k];
            if (p.is_list)
                throw Error(pre + ": vertex property '" + core::printable(p.name, 40) +
                            "' is a list; allowed: scalars");
            Column c;
            c.present = true;
            c.type = p.type;
            c.base = offset;
            c.token = k;
            Column* slot = nullptr;
            if (p.name == "x")
                slot = &l.x;
            else if (p.name == "y")
                slot = &l.y;
            else if (p.name == "z")
                slot = &l.z;
            else if (p.name == "red" || p.name == "r" || p.name == "diffuse_red")
                slot = &l.red;
            else if (p.name == "green" || p.name == "g" || p.name == "diffuse_green")
                slot = &l.green;
            else if (p.name == "blue" || p.name == "b" || p.name == "diffuse_blue")
                slot = &l.blue;
            else
                slot = columnFor(l, p.name);
            // What the label's codes mean: ours, ASPRS classes, or both (LabelCodes).
            if (slot == &l.label && !l.label.present) l.label_codes = labelCodesFor(p.name, ours);
            if (slot && !slot->present) *slot = c;
            offset += std::size_t(p.type.size);
        }
        if (!l.x.present || !l.y.present || !l.z.present)
            throw Error(pre + ": the vertex element has no x, y and z properties; they are required");
        l.colour_float = l.red.present && l.red.type.kind == Kind::Float;
        record_ = offset;
        fields = l.fields();
        for (Column* c : {&l.x, &l.y, &l.z, &l.red, &l.green, &l.blue, &l.label, &l.view, &l.range, &l.intensity,
                          &l.return_number, &l.returns, &l.incidence, &l.scan_angle, &l.height_above_ground})
            c->stride = record_;
    }

    void skipTextElements() {
        for (std::size_t e = 0; e < vi_; ++e) {
            const PlyElement& el = elements_[e];
            if (el.props.empty()) continue;
            const std::string truncated = prefix_ + ": truncated in element '" + core::printable(el.name, 40) + "'";
            for (std::size_t i = 0; i < el.count; ++i) {
                for (const PlyProperty& p : el.props) {
                    std::string_view tok;
                    std::size_t items = 1;
                    if (!tokens_->next(tok)) throw Error(truncated);
                    if (p.is_list) {
                        if (!parseExact(tok, items))
                            throw Error(prefix_ + ": line " + std::to_string(lines_ + tokens_->lineNo()) +
                                        ": list count '" + core::printable(tok, 20) +
                                        "' is not a non-negative integer");
                        for (std::size_t k = 0; k < items; ++k)
                            if (!tokens_->next(tok)) throw Error(truncated);
                    }
                }
            }
        }
    }

    void skipBinaryElements() {
        const bool swap = format_ == "binary_big_endian";
        const std::uint64_t size = source_.size();
        std::uint64_t pos = body_;
        for (std::size_t e = 0; e < vi_; ++e) {
            const PlyElement& el = elements_[e];
            if (el.props.empty()) continue;
            const std::string truncated = prefix_ + ": truncated in element '" + core::printable(el.name, 40) + "'";
            bool has_list = false;
            std::size_t fixed = 0;
            for (const PlyProperty& p : el.props) {
                has_list = has_list || p.is_list;
                fixed += std::size_t(p.type.size);
            }
            if (!has_list) {
                if (el.count > (size - pos) / fixed) throw Error(truncated);
                pos += el.count * fixed;
                continue;
            }
            for (std::size_t i = 0; i < el.count; ++i) {
                for (const PlyProperty& p : el.props) {
                    std::size_t items = 1;
                    if (p.is_list) {
                        if (std::uint64_t(p.count_type.size) > size - pos) throw Error(truncated);
                        const std::string_view c = source_.view(pos, std::size_t(p.count_type.size));
                        pos += std::size_t(p.count_type.size);
                        if (!listCount(reinterpret_cast<const unsigned char*>(c.data()), p.count_type, swap, items))
                            throw Error(prefix_ + ": element '" + core::printable(el.name, 40) + "' " +
                                        std::to_string(i) + ": bad list count");
                    }
                    if (items > (size - pos) / std::size_t(p.type.size)) throw Error(truncated);
                    pos += items * std::size_t(p.type.size);
                }
            }
        }
        const std::uint64_t remaining = size - pos;
        if (declared > remaining / record_)
            throw Error(prefix_ + ": truncated: the header says " + std::to_string(declared) + " vertices of " +
                        std::to_string(record_) + " bytes but only " + std::to_string(remaining) +
                        " bytes of data follow");
        vertex_at_ = pos;
        if (last_)
            checkPadding(source_, pos + declared * record_, prefix_,
                         std::to_string(declared) + " vertices the header declares");
    }

    ByteSource& source_;
    std::string prefix_;
    std::optional<TextStream> tokens_;  // after the header
    std::string format_;
    std::vector<PlyElement> elements_;
    Layout layout_;
    bool ours = false;    // the header has the ladarvr origin comment
    std::size_t vi_ = 0;  // the vertex element
    bool last_ = true;    // no element with data follows the vertices
    std::size_t record_ = 0;
    std::size_t lines_ = 0;
    std::uint64_t body_ = 0, vertex_at_ = 0;
    std::size_t done_ = 0;
    bool end_checked_ = false;
};

}  // namespace

std::unique_ptr<FormatReader> openPly(ByteSource& source, const std::string& prefix) {
    return std::make_unique<PlyReader>(source, prefix);
}

}  // namespace io::detail
