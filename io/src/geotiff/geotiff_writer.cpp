// io/src/geotiff/geotiff_writer.cpp: io/geotiff.hpp. A little-endian classic TIFF, or a
// BigTIFF where the grid needs one (the same layout with 64-bit offsets and counts: a
// 16-byte header, IFD entries of 20 bytes).
// Uncompressed: the header, one IFD right after it, the tags' values that do not
// fit in their entry, then the rows of heights, each a strip of its own. Deflate: the
// header, the strips (rows of at most 64 KiB together, each row through the
// floating-point predictor, then zlib), then the IFD and its values, whose place the
// header is given once the strips' sizes are known. The keys come from the WKT through
// PROJ (a context per call, logging off, as the LAS reader's CRS conversion does).
#include <io/geotiff.hpp>

#include <core/error.hpp>

#include "../proj_ptr.hpp"

#include <algorithm>
#include <bit>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <memory>
#include <string>

#include <zlib.h>

namespace io {
namespace {

static_assert(std::endian::native == std::endian::little, "the heights are written as the host holds them");

using detail::Pj;
using detail::ProjContext;

// GeoTIFF 1.1 key ids and codes.
enum : std::uint16_t {
    kModelType = 1024,
    kRasterType = 1025,
    kCitation = 1026,
    kGeographicType = 2048,
    kGeogCitation = 2049,
    kGeogAngularUnits = 2054,
    kProjectedType = 3072,
    kProjLinearUnits = 3076,
    kVerticalType = 4096,
    kVerticalCitation = 4097,
    kVerticalUnits = 4099,
};
constexpr std::uint16_t kUserDefined = 32767;
constexpr std::uint16_t kModelProjected = 1, kModelGeographic = 2, kModelGeocentric = 3;
constexpr std::uint16_t kPixelIsArea = 1;

// A WKT's BoundCRS (WKT 1 with TOWGS84) is its source CRS with a transformation: the
// keys describe the source.
Pj unbound(PJ_CONTEXT* ctx, Pj pj) {
    if (pj && proj_get_type(pj.get()) == PJ_TYPE_BOUND_CRS)
        if (Pj source = Pj(proj_get_source_crs(ctx, pj.get()))) return source;
    return pj;
}

// An EPSG code that fits a key (1..32766): the object's own, else the one PROJ identifies
// with full confidence; 0 when there is none.
std::uint16_t epsgOf(PJ_CONTEXT* ctx, const PJ* pj) {
    const auto fits = [](const char* auth, const char* code) -> std::uint16_t {
        if (!auth || !code || std::strcmp(auth, "EPSG") != 0) return 0;
        char* end = nullptr;
        const long v = std::strtol(code, &end, 10);
        return end && *end == '\0' && v > 0 && v < kUserDefined ? std::uint16_t(v) : 0;
    };
    if (const std::uint16_t own = fits(proj_get_id_auth_name(pj, 0), proj_get_id_code(pj, 0))) return own;
    int* confidence = nullptr;
    PJ_OBJ_LIST* list = proj_identify(ctx, pj, "EPSG", nullptr, &confidence);
    std::uint16_t found = 0;
    if (list && proj_list_get_count(list) > 0 && confidence && confidence[0] == 100)
        if (const Pj best = Pj(proj_list_get(ctx, list, 0)))
            found = fits(proj_get_id_auth_name(best.get(), 0), proj_get_id_code(best.get(), 0));
    proj_int_list_destroy(confidence);
    proj_list_destroy(list);
    return found;
}

// The EPSG code of the unit of the CRS's first axis: the unit's own, else the one of its
// length for metre, foot and US survey foot (a unit named without a code); 0 unknown.
std::uint16_t unitOf(PJ_CONTEXT* ctx, const PJ* crs) {
    const Pj cs(proj_crs_get_coordinate_system(ctx, crs));
    double factor = 0.0;
    const char* auth = nullptr;
    const char* code = nullptr;
    if (!cs || !proj_cs_get_axis_info(ctx, cs.get(), 0, nullptr, nullptr, nullptr, &factor, nullptr, &auth, &code))
        return 0;
    if (auth && code && std::strcmp(auth, "EPSG") == 0) {
        const long v = std::strtol(code, nullptr, 10);
        if (v > 0 && v < kUserDefined) return std::uint16_t(v);
    }
    struct Known {
        double metres;
        std::uint16_t code;
    };
    for (const Known k : {Known{1.0, 9001}, Known{0.3048, 9002}, Known{1200.0 / 3937.0, 9003}})
        if (std::fabs(factor - k.metres) <= 1e-9 * k.metres) return k.code;
    return 0;
}

std::string nameOf(const PJ* pj) {
    const char* n = proj_get_name(pj);
    std::string s;
    for (const char* c = n ? n : ""; *c; ++c)
        if (*c >= 0x20 && *c < 0x7f && *c != '|' && s.size() < 200) s.push_back(*c);
    return s.empty() ? "unknown" : s;
}

void put16(std::string& b, std::uint16_t v) {
    b.push_back(char(v & 0xff));
    b.push_back(char(v >> 8));
}
void put32(std::string& b, std::uint32_t v) {
    for (int k = 0; k < 4; ++k) b.push_back(char((v >> (8 * k)) & 0xff));
}
void put64(std::string& b, std::uint64_t v) {
    for (int k = 0; k < 8; ++k) b.push_back(char((v >> (8 * k)) & 0xff));
}
void putDouble(std::string& b, double v) {
    std::uint64_t bits;
    std::memcpy(&bits, &v, sizeof bits);
    for (int k = 0; k < 8; ++k) b.push_back(char((bits >> (8 * k)) & 0xff));
}

// TIFF field types.
constexpr std::uint16_t kAscii = 2, kShort = 3, kLong = 4, kDouble = 12, kLong8 = 16;

struct Tag {
    std::uint16_t id, type;
    std::uint64_t count;
    std::string bytes;  // the value, little-endian
};

// Where the heights lie: rows_per_strip rows a strip, each strip's offset and size.
struct Strips {
    std::uint32_t rows_per_strip = 1;
    std::vector<std::uint64_t> offsets, counts;
};

// The header's size: classic TIFF's 8 bytes, BigTIFF's 16.
std::uint64_t headerBytes(bool big) { return big ? 16 : 8; }

// Rows a Deflate strip holds: as many as fit in 64 KiB, at least one.
std::uint32_t deflateRowsPerStrip(const GeoTiffGrid& grid) {
    const std::uint64_t row_bytes = std::uint64_t(grid.columns) * 4u;
    return std::uint32_t(std::clamp<std::uint64_t>((64u << 10) / row_bytes, 1, std::uint64_t(grid.rows)));
}

// Uncompressed: one row a strip, the strips one after another from `data_at`.
Strips plainStrips(const GeoTiffGrid& grid, std::uint64_t data_at) {
    const std::uint64_t row_bytes = std::uint64_t(grid.columns) * 4u;
    Strips s;
    for (std::uint32_t r = 0; r < std::uint32_t(grid.rows); ++r) {
        s.offsets.push_back(data_at + std::uint64_t(r) * row_bytes);
        s.counts.push_back(row_bytes);
    }
    return s;
}

// The tags of `grid` with `keys` and the heights in `strips`; in a BigTIFF (`big`) the
// strips' offsets and sizes are 64-bit.
std::vector<Tag> tagsFor(const GeoTiffGrid& grid, const std::vector<GeoKey>& keys, const Strips& strips, bool big) {
    const std::uint32_t rows = std::uint32_t(grid.rows);
    std::vector<Tag> tags;
    const auto shortTag = [&](std::uint16_t id, std::uint16_t v) {
        std::string b;
        put16(b, v);
        tags.push_back({id, kShort, 1, b});
    };
    const auto longTag = [&](std::uint16_t id, std::uint32_t v) {
        std::string b;
        put32(b, v);
        tags.push_back({id, kLong, 1, b});
    };
    longTag(256, std::uint32_t(grid.columns));  // ImageWidth
    longTag(257, rows);                         // ImageLength
    shortTag(258, 32);                          // BitsPerSample
    shortTag(259, grid.deflate ? 8 : 1);        // Compression: Deflate (Adobe's code, as GDAL writes) or none
    shortTag(262, 1);                           // PhotometricInterpretation: BlackIsZero
    std::string offsets, counts;
    for (std::size_t k = 0; k < strips.offsets.size(); ++k) {
        if (big) {
            put64(offsets, strips.offsets[k]);
            put64(counts, strips.counts[k]);
        } else {
            put32(offsets, std::uint32_t(strips.offsets[k]));
            put32(counts, std::uint32_t(strips.counts[k]));
        }
    }
    const std::uint64_t n = strips.offsets.size();
    const std::uint16_t offset_type = big ? kLong8 : kLong;
    tags.push_back({273, offset_type, n, offsets});  // StripOffsets
    shortTag(277, 1);                                // SamplesPerPixel
    longTag(278, strips.rows_per_strip);             // RowsPerStrip
    tags.push_back({279, offset_type, n, counts});   // StripByteCounts
    shortTag(284, 1);                                // PlanarConfiguration: contiguous
    if (grid.deflate) shortTag(317, 3);              // Predictor: floating point (TIFF Technical Note 3)
    shortTag(339, 3);                                // SampleFormat: IEEE floating point
    std::string scale, tie;
    for (const double v : {grid.cell, grid.cell, 0.0}) putDouble(scale, v);
    for (const double v : {0.0, 0.0, 0.0, grid.west, grid.north, 0.0}) putDouble(tie, v);
    tags.push_back({33550, kDouble, 3, scale});  // ModelPixelScaleTag
    tags.push_back({33922, kDouble, 6, tie});    // ModelTiepointTag: raster (0, 0) at the top-left corner
    if (!keys.empty()) {
        std::string directory, ascii;
        put16(directory, 1);  // KeyDirectoryVersion
        put16(directory, 1);  // KeyRevision
        put16(directory, 1);  // MinorRevision: GeoTIFF 1.1
        put16(directory, std::uint16_t(keys.size()));
        for (const GeoKey& k : keys) {
            put16(directory, k.id);
            if (k.text.empty()) {
                put16(directory, 0);
                put16(directory, 1);
                put16(directory, k.value);
            } else {
                put16(directory, 34737);
                put16(directory, std::uint16_t(k.text.size() + 1));
                put16(directory, std::uint16_t(ascii.size()));
                ascii += k.text + '|';
            }
        }
        tags.push_back({34735, kShort, std::uint32_t(directory.size() / 2), directory});  // GeoKeyDirectoryTag
        if (!ascii.empty()) {
            ascii.push_back('\0');
            tags.push_back({34737, kAscii, std::uint32_t(ascii.size()), ascii});  // GeoAsciiParamsTag
        }
    }
    const std::string nodata = "-9999";
    tags.push_back({42113, kAscii, std::uint32_t(nodata.size() + 1), nodata + '\0'});  // GDAL_NODATA
    return tags;
}

// The IFD and the values outside their entries (each at an even offset), to be written at
// `at` (even). Its size depends only on the tags' sizes. Classic TIFF: a 2-byte entry
// count, entries of 12 bytes holding a value of up to 4 bytes, a 4-byte link; BigTIFF: 8,
// 20 holding up to 8, 8.
std::string ifdAt(const std::vector<Tag>& tags, std::uint64_t at, bool big) {
    const std::uint64_t inline_bytes = big ? 8 : 4;
    const std::uint64_t ifd_bytes = big ? 8 + 20 * tags.size() + 8 : 2 + 12 * tags.size() + 4;
    const auto word = [&](std::string& b, std::uint64_t v) { big ? put64(b, v) : put32(b, std::uint32_t(v)); };
    std::string head;
    std::string extra;
    if (big)
        put64(head, tags.size());
    else
        put16(head, std::uint16_t(tags.size()));
    for (const Tag& t : tags) {
        put16(head, t.id);
        put16(head, t.type);
        word(head, t.count);
        if (t.bytes.size() <= inline_bytes) {
            head += t.bytes;
            head.append(inline_bytes - t.bytes.size(), '\0');
        } else {
            word(head, at + ifd_bytes + extra.size());
            extra += t.bytes;
            if (extra.size() % 2) extra.push_back('\0');
        }
    }
    word(head, 0);  // no next IFD
    return head + extra;
}

// The TIFF header pointing at the first IFD: byte order, 42 and the offset; BigTIFF: byte
// order, 43, the offsets' size (8), 0 and the offset.
std::string headerFor(std::uint64_t ifd_at, bool big) {
    std::string b = "II";
    if (big) {
        put16(b, 43);
        put16(b, 8);
        put16(b, 0);
        put64(b, ifd_at);
    } else {
        put16(b, 42);
        put32(b, std::uint32_t(ifd_at));
    }
    return b;
}

// The bytes before the heights of an uncompressed file: header, IFD and its values. Its
// size does not depend on where the strips lie.
std::string headOf(const std::vector<Tag>& tags, bool big) {
    return headerFor(headerBytes(big), big) + ifdAt(tags, headerBytes(big), big);
}

// One row through the floating-point predictor: each height's bytes spread over four
// planes, its most significant byte in the first, then each byte less the one before it.
void predictRow(const float* values, std::size_t columns, unsigned char* out) {
    for (std::size_t i = 0; i < columns; ++i) {
        std::uint32_t bits;
        std::memcpy(&bits, &values[i], sizeof bits);
        for (std::size_t b = 0; b < 4; ++b) out[b * columns + i] = (unsigned char)(bits >> (8 * (3 - b)));
    }
    for (std::size_t k = 4 * columns; k-- > 1;) out[k] = (unsigned char)(out[k] - out[k - 1]);
}

// Bytes a Deflate file of `grid` with `keys` takes at most: each strip compressed no
// smaller than zlib's bound says, the IFD after them.
std::uint64_t deflateBoundBytes(const GeoTiffGrid& grid, const std::vector<GeoKey>& keys, bool big) {
    const std::uint32_t per = deflateRowsPerStrip(grid);
    const std::uint32_t n = (std::uint32_t(grid.rows) + per - 1) / per;
    const std::uint64_t row_bytes = std::uint64_t(grid.columns) * 4u;
    std::uint64_t bytes = headerBytes(big);
    for (std::uint32_t k = 0; k < n; ++k) {
        const std::uint64_t rows = std::min<std::uint64_t>(per, std::uint64_t(grid.rows) - std::uint64_t(k) * per);
        bytes += compressBound(uLong(rows * row_bytes));
    }
    Strips sizing;
    sizing.offsets.assign(n, 0);
    sizing.counts.assign(n, 0);
    return bytes + 1 + ifdAt(tagsFor(grid, keys, sizing, big), 0, big).size();
}

// The file's size (at most, with Deflate) as a classic TIFF or as a BigTIFF.
std::uint64_t bytesAs(const GeoTiffGrid& grid, const std::vector<GeoKey>& keys, bool big) {
    if (grid.deflate) return deflateBoundBytes(grid, keys, big);
    const std::uint64_t head = headOf(tagsFor(grid, keys, plainStrips(grid, 0), big), big).size();
    return head + (head % 4 ? 4 - head % 4 : 0) + std::uint64_t(grid.columns) * std::uint64_t(grid.rows) * 4u;
}

constexpr std::uint64_t kClassicMaxBytes = 0xffffffffu;

}  // namespace

std::vector<GeoKey> geoKeysForWkt(std::string_view wkt_in, std::string& problem) {
    problem.clear();
    std::string wkt(wkt_in.substr(0, wkt_in.find('\0')));
    if (wkt.find_first_not_of(" \t\r\n") == std::string::npos) return {};
    const ProjContext ctx(proj_context_create());
    if (!ctx) {
        problem = "PROJ could not be started";
        return {};
    }
    proj_log_level(ctx.get(), PJ_LOG_NONE);
    Pj crs = unbound(ctx.get(), Pj(proj_create(ctx.get(), wkt.c_str())));
    if (!crs || !proj_is_crs(crs.get())) {
        problem = "PROJ cannot read the CRS's WKT";
        return {};
    }
    Pj horizontal, vertical;
    const PJ_TYPE type = proj_get_type(crs.get());
    if (type == PJ_TYPE_COMPOUND_CRS) {
        horizontal = unbound(ctx.get(), Pj(proj_crs_get_sub_crs(ctx.get(), crs.get(), 0)));
        vertical = unbound(ctx.get(), Pj(proj_crs_get_sub_crs(ctx.get(), crs.get(), 1)));
    } else if (type == PJ_TYPE_VERTICAL_CRS) {
        vertical = std::move(crs);
    } else {
        horizontal = std::move(crs);
    }
    std::vector<GeoKey> keys;
    const auto add = [&](std::uint16_t id, std::uint16_t value) { keys.push_back({id, value, {}}); };
    const auto text = [&](std::uint16_t id, const std::string& s) { keys.push_back({id, 0, s}); };
    if (horizontal) {
        const PJ_TYPE h = proj_get_type(horizontal.get());
        const std::uint16_t code = epsgOf(ctx.get(), horizontal.get());
        const std::uint16_t unit = unitOf(ctx.get(), horizontal.get());
        if (h == PJ_TYPE_PROJECTED_CRS) {
            add(kModelType, kModelProjected);
            add(kRasterType, kPixelIsArea);
            if (!code) text(kCitation, nameOf(horizontal.get()));
            add(kProjectedType, code ? code : kUserDefined);
            if (unit) add(kProjLinearUnits, unit);
        } else if (h == PJ_TYPE_GEOGRAPHIC_2D_CRS || h == PJ_TYPE_GEOGRAPHIC_3D_CRS) {
            add(kModelType, kModelGeographic);
            add(kRasterType, kPixelIsArea);
            add(kGeographicType, code ? code : kUserDefined);
            if (!code) text(kGeogCitation, nameOf(horizontal.get()));
            if (unit) add(kGeogAngularUnits, unit);
        } else if (h == PJ_TYPE_GEOCENTRIC_CRS) {
            add(kModelType, kModelGeocentric);
            add(kRasterType, kPixelIsArea);
            if (!code) text(kCitation, nameOf(horizontal.get()));
        } else {
            problem = "the horizontal CRS is of a kind GeoTIFF keys do not describe";
            return {};
        }
    } else {
        add(kRasterType, kPixelIsArea);
    }
    if (vertical) {
        const std::uint16_t code = epsgOf(ctx.get(), vertical.get());
        add(kVerticalType, code ? code : kUserDefined);
        if (!code) text(kVerticalCitation, nameOf(vertical.get()));
        if (const std::uint16_t unit = unitOf(ctx.get(), vertical.get())) add(kVerticalUnits, unit);
    }
    std::sort(keys.begin(), keys.end(), [](const GeoKey& a, const GeoKey& b) { return a.id < b.id; });
    return keys;
}

bool geoTiffIsBig(const GeoTiffGrid& grid, const std::vector<GeoKey>& keys) {
    switch (grid.kind) {
        case TiffKind::classic: return false;
        case TiffKind::big: return true;
        case TiffKind::automatic: break;
    }
    return grid.columns > 0 && grid.rows > 0 && bytesAs(grid, keys, false) > kClassicMaxBytes;
}

std::uint64_t geoTiffBytes(const GeoTiffGrid& grid, const std::vector<GeoKey>& keys) {
    if (grid.columns <= 0 || grid.rows <= 0) return 0;
    return bytesAs(grid, keys, geoTiffIsBig(grid, keys));
}

void writeGeoTiff(std::FILE* out, const GeoTiffGrid& grid, const std::vector<GeoKey>& keys,
                  const std::function<void(int, float*)>& row, const std::string& what) {
    const std::string prefix = "output: " + what + ": ";
    if (grid.columns <= 0 || grid.rows <= 0)
        throw core::Error(prefix + "a grid of " + std::to_string(grid.columns) + " x " + std::to_string(grid.rows) +
                          " cells; allowed at least 1 x 1");
    if (!(std::isfinite(grid.cell) && grid.cell > 0.0) || !std::isfinite(grid.west) || !std::isfinite(grid.north))
        throw core::Error(prefix + "the grid's corner and cell must be finite, the cell > 0");
    const bool big = geoTiffIsBig(grid, keys);
    const std::uint64_t bytes = bytesAs(grid, keys, big);
    if (!big && bytes > kClassicMaxBytes)
        throw core::Error(prefix + "a grid of " + std::to_string(grid.columns) + " x " + std::to_string(grid.rows) +
                          " cells takes " + std::to_string(bytes) +
                          " bytes; a classic TIFF holds at most 4 GiB: write it as a BigTIFF instead");
    const auto put = [&](const void* data, std::size_t n) {
        if (std::fwrite(data, 1, n, out) != n) throw core::Error(prefix + "write failed: " + std::strerror(errno));
    };
    std::vector<float> values(static_cast<std::size_t>(grid.columns));
    const auto next = [&](int r) {
        std::fill(values.begin(), values.end(), std::nanf(""));
        row(r, values.data());
        for (float& v : values)
            if (!std::isfinite(v)) v = kGeoTiffNoData;
    };
    if (!grid.deflate) {
        // The heights start at a multiple of 4 after the head, whose size the offsets leave alone.
        std::size_t head_bytes = headOf(tagsFor(grid, keys, plainStrips(grid, 0), big), big).size();
        head_bytes += head_bytes % 4 ? 4 - head_bytes % 4 : 0;
        std::string head = headOf(tagsFor(grid, keys, plainStrips(grid, head_bytes), big), big);
        head.resize(head_bytes, '\0');
        put(head.data(), head.size());
        for (int r = 0; r < grid.rows; ++r) {
            next(r);
            put(values.data(), values.size() * sizeof(float));
        }
    } else {
        const long start = std::ftell(out);
        if (start < 0) throw core::Error(prefix + "cannot tell the file's position: " + std::strerror(errno));
        put(headerFor(0, big).data(), headerBytes(big));
        Strips strips;
        strips.rows_per_strip = deflateRowsPerStrip(grid);
        const std::size_t row_bytes = values.size() * sizeof(float);
        std::vector<unsigned char> raw(row_bytes * strips.rows_per_strip);
        std::vector<unsigned char> packed(compressBound(uLong(raw.size())));
        std::uint64_t at = headerBytes(big);
        for (int r0 = 0; r0 < grid.rows; r0 += int(strips.rows_per_strip)) {
            const int rows = std::min(int(strips.rows_per_strip), grid.rows - r0);
            for (int r = 0; r < rows; ++r) {
                next(r0 + r);
                predictRow(values.data(), values.size(), raw.data() + std::size_t(r) * row_bytes);
            }
            uLongf size = uLongf(packed.size());
            if (compress2(packed.data(), &size, raw.data(), uLong(std::size_t(rows) * row_bytes), 6) != Z_OK)
                throw core::Error(prefix + "Deflate failed on rows " + std::to_string(r0) + "+");
            put(packed.data(), size);
            strips.offsets.push_back(at);
            strips.counts.push_back(size);
            at += size;
        }
        if (at % 2) {
            put("", 1);
            ++at;
        }
        const std::string ifd = ifdAt(tagsFor(grid, keys, strips, big), at, big);
        put(ifd.data(), ifd.size());
        if (std::fseek(out, start, SEEK_SET) != 0)
            throw core::Error(prefix + "cannot go back to the header: " + std::strerror(errno));
        put(headerFor(at, big).data(), headerBytes(big));
        if (std::fseek(out, 0, SEEK_END) != 0)
            throw core::Error(prefix + "cannot go back to the end: " + std::strerror(errno));
    }
    if (std::fflush(out) != 0) throw core::Error(prefix + "write failed: " + std::strerror(errno));
}

}  // namespace io
