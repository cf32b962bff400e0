// io/src/cloud_decode.hpp (internal): what the PCD and PLY readers share: the byte
// sources they read from (a file read piece by piece, or bytes in memory), a text token
// stream over a source, the description of the fields we keep (Layout) and the decoding
// of binary and text records into CloudPoints. Every read is bounded by the source's
// size, so no header count can make a reader allocate or read past the file.
#pragma once
#include <core/point_cloud.hpp>

#include <charconv>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace io::detail {

/// Random-access bytes of a cloud file. view() returns exactly `n` bytes starting at
/// `offset` (the caller checks offset + n <= size()); the view stays valid until the
/// next call. Throws Error("<prefix>: ...") if the bytes cannot be read.
class ByteSource {
  public:
    virtual ~ByteSource() = default;
    std::uint64_t size() const { return size_; }
    virtual std::string_view view(std::uint64_t offset, std::size_t n) = 0;

  protected:
    std::uint64_t size_ = 0;
};

/// Bytes already in memory (they must outlive the source).
std::unique_ptr<ByteSource> memorySource(std::string_view bytes);
/// A regular file, read with pread through a 1 MiB window (sequential small reads are
/// cheap, large ones go straight into one reused buffer). `module` ("pcd", "ply") starts
/// the messages. Throws Error("<module>: <path>: file does not exist" / "...: is a
/// directory, not a regular file" / ...).
std::unique_ptr<ByteSource> fileSource(const std::filesystem::path& path, const char* module);

/// The reader a file's content calls for: "las", "ply" or "pcd". PLY files start with
/// "ply", LAS and LAZ with "LASF"; everything else is read as PCD (whose header may start
/// with any comment), except a file named .las or .laz: the LAS reader says what it lacks
/// (an empty or cut file is no PCD either).
const char* moduleOf(ByteSource& source, const std::filesystem::path& name);

/// Whitespace-separated tokens of the text after `begin`, with line numbers (1 = the
/// first line after `begin`). A token is valid until the next call.
class TextStream {
  public:
    TextStream(ByteSource& source, std::uint64_t begin, std::string prefix);
    /// False at the end of the data. Throws Error for a token longer than 4,096 bytes.
    bool next(std::string_view& token);
    std::size_t lineNo() const { return line_no_; }

  private:
    bool refill();
    ByteSource& source_;
    std::uint64_t next_;  // file offset just after block_
    std::string_view block_;
    std::size_t at_ = 0;
    std::size_t line_no_ = 1;
    std::string long_token_;
    std::string prefix_;
};

/// The header text of a source: its first bytes up to 1 MiB (the PCD and PLY headers
/// must end within them).
std::string headerPrefix(ByteSource& source);
inline constexpr std::size_t kMaxHeaderBytes = 1u << 20;
inline constexpr std::size_t kMaxHeaderLines = 10000;

/// Reads header lines (without "\n" and a trailing "\r"); false at the end of the text.
struct LineReader {
    std::string_view data;
    std::size_t pos = 0;
    std::size_t line_no = 0;
    bool next(std::string_view& line);
};

enum class Kind : std::uint8_t { Int, UInt, Float };

struct ScalarType {
    Kind kind = Kind::Float;
    int size = 4;
};

/// The codes of a label field: our roles 0..2 only (files we wrote: the ladarvr origin
/// comment), ASPRS classes (a field named `classification`), or, in other files' `label`,
/// our roles for 0..2 and ASPRS classes from 3 on (6 building, ...), which PCL-converted
/// copies of our clouds and ASPRS-labelled clouds both read as meant.
enum class LabelCodes : std::uint8_t { Roles, RolesThenClasses, Classes };

/// The label codes a file's field `name` holds; `ours`: the header has the ladarvr origin.
LabelCodes labelCodesFor(std::string_view name, bool ours);

/// One field we use: where its value sits in the (decoded) data.
struct Column {
    bool present = false;
    ScalarType type;
    std::size_t base = 0;    // byte offset of point 0
    std::size_t stride = 0;  // bytes between points
    std::size_t token = 0;   // index of the value within a text record
};

/// What each field we keep is, in one format's records.
struct Layout {
    Column x, y, z, rgb, red, green, blue, label, view, range;
    Column intensity, return_number, returns, incidence, scan_angle, height_above_ground;
    bool rgb_float_text = false;  // PCD rgb of TYPE F in text: uint32 bits or a float
    bool colour_float = false;    // PLY red/green/blue as floats in [0, 1]
    /// What the label's codes mean (docs/formats.md).
    LabelCodes label_codes = LabelCodes::Roles;
    /// Subtracted from x, y, z in double precision before the cast to float, so
    /// georeferenced double coordinates keep their millimetres (added to the origin).
    glm::dvec3 shift{0.0};
    core::CloudFields fields() const;
    /// Whether x, y, z hold more precision than a float (double or integer columns).
    bool wideXyz() const;
};

/// Where a field name is one of ours (x, y, z excepted): "label" and "scalar_label"
/// (CloudCompare keeps only `scalar_*` properties) alike. Null for unknown names.
Column* columnFor(Layout& l, std::string_view name);

/// The shift for georeferenced coordinates: per axis, the whole metres of `first` (the
/// first point) when |first| >= kShiftFrom_m, else 0. Floats of 4 bytes reach 1 mm steps
/// at 8,192 m, so smaller coordinates are kept exactly as they are.
glm::dvec3 shiftFor(const glm::dvec3& first);
inline constexpr double kShiftFrom_m = 4096.0;

/// Our role for an ASPRS class (LAS 1.4 R15 table 17): 2 -> ground, the other standard
/// classes 0..22 -> environment, kTargetClass -> target. Unknown codes -> environment and
/// `known` = false.
core::Role roleForClass(unsigned code, bool& known);
inline constexpr unsigned kTargetClass = 64;  // the first user-definable class

/// Counters the decoders keep across chunks (for the reader's warning line).
struct DecodeStats {
    std::size_t unknown_classes = 0;
    unsigned first_unknown = 0;
};

std::vector<std::string_view> splitWords(std::string_view line);
/// `s` as a whole number of T (an integer type, or float), nothing before or after it;
/// false when it is not one or out of T's range.
template <class T>
bool parseExact(std::string_view s, T& out) {
    const auto r = std::from_chars(s.data(), s.data() + s.size(), out);
    return r.ec == std::errc() && r.ptr == s.data() + s.size();
}
/// A number; out of range gives +-inf (overflow) or the nearest denormal/0 (underflow).
bool parseDouble(std::string_view s, double& out);
/// "X Y Z" at words[first..first+2], each finite. Throws Error(where + ": ...").
glm::dvec3 parseOrigin(const std::vector<std::string_view>& words, std::size_t first, const std::string& where);
/// Zero bytes after the declared data are padding (PCL pads its binary files so); up to
/// 64 KiB of them are accepted, anything else is refused with one line naming `what`.
void checkPadding(ByteSource& source, std::uint64_t from, const std::string& prefix, const std::string& what);

/// Decodes `count` binary records into `out` (appended): the record of point k (k from 0)
/// is read through Column base + (first + k) * stride from `data`; `number` is the index
/// of the first point in the file, for messages. `swap`: big-endian data.
void decodeBinary(const unsigned char* data, std::size_t first, std::size_t count, const Layout& l, bool swap,
                  std::size_t number, const std::string& prefix, std::vector<core::CloudPoint>& out,
                  DecodeStats& stats);

/// Decodes `count` text records of `per_point` tokens each (appended to `out`); `number`
/// is the index of the first, `line_base` the header's line count (for messages), `total`
/// the declared count (for the truncation message).
void decodeText(TextStream& tokens, std::size_t count, std::size_t per_point, const Layout& l, std::size_t number,
                std::size_t total, std::size_t line_base, const std::string& prefix, std::vector<core::CloudPoint>& out,
                DecodeStats& stats);

/// x, y, z of the first text record (for shiftFor), read through a stream of its own
/// that starts at the record; false if the data end first or a value is no number.
bool peekTextXyz(TextStream& tokens, const Layout& l, std::size_t per_point, glm::dvec3& xyz);
/// x, y, z of the binary record at `record` (for shiftFor).
glm::dvec3 peekBinaryXyz(const unsigned char* record, const Layout& l, bool swap);

/// One cloud format's reader: the header is read and checked when it is made; next()
/// then decodes the records in order.
class FormatReader {
  public:
    virtual ~FormatReader() = default;
    /// Appends up to `max_points` (>= 1) decoded points to `out` and returns how many;
    /// 0 once every declared point is read (and the data end was checked).
    virtual std::size_t next(std::vector<core::CloudPoint>& out, std::size_t max_points) = 0;

    glm::dvec3 origin{0.0};
    core::CloudFields fields;
    std::size_t declared = 0;  // the header's point count
    std::size_t bound = 0;     // at most this many points fit in the data (for reserve)
    DecodeStats stats;
    /// Set by a LAS/LAZ reader opened to keep side records of a foreign file; next() then
    /// appends each point's record (foreign->stride() bytes) to *foreign_out.
    std::shared_ptr<const core::ForeignHeader> foreign;
    std::vector<unsigned char>* foreign_out = nullptr;
};

/// The PCD v0.7 reader (ascii, binary, binary_compressed). Throws Error("<prefix>: ...").
std::unique_ptr<FormatReader> openPcd(ByteSource& source, const std::string& prefix);
/// The PLY 1.0 reader (ascii, binary little and big endian). Throws Error("<prefix>: ...").
std::unique_ptr<FormatReader> openPly(ByteSource& source, const std::string& prefix);
/// The LAS 1.0-1.4 / LAZ reader (LASzip). Throws Error("<prefix>: ...").
/// With `keep_foreign`, a file without our `label` extra bytes keeps side records
/// (FormatReader::foreign). With `positions_only`, a LAZ file of LAS 1.4's layered point
/// formats (6-10) has LASzip decode only what PointFields::Positions names.
std::unique_ptr<FormatReader> openLas(ByteSource& source, const std::string& prefix, bool keep_foreign = false,
                                      bool positions_only = false);

}  // namespace io::detail
