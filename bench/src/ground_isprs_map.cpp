// bench/src/ground_isprs_map.cpp: the error picture of `bench ground-isprs --map`
// (ground_isprs_map.hpp). Points are splatted as small squares, the right ones first and
// the errors over them; labels use a 3 x 5 pixel digit font scaled up, on a background box.
#include "ground_isprs_map.hpp"

#include <core/error.hpp>
#include <core/point_cloud.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace bench {
namespace {

// Each digit's five rows of three pixels, the leftmost the highest bit.
constexpr std::uint8_t kDigits[10][5] = {
    {7, 5, 5, 5, 7}, {2, 6, 2, 2, 7}, {7, 1, 7, 4, 7}, {7, 1, 7, 1, 7}, {5, 5, 7, 1, 1},
    {7, 4, 7, 1, 7}, {7, 4, 7, 5, 7}, {7, 1, 1, 1, 1}, {7, 5, 7, 5, 7}, {7, 5, 7, 1, 7},
};
constexpr int kFontScale = 3;  // each font pixel as a square of this many image pixels
constexpr int kLabelMargin_px = 2;
constexpr int kRightDot_px = 2;  // side of the square a right point is drawn as
constexpr int kErrorDot_px = 3;  // and an error

void fill(MapImage& image, int x0, int y0, int w, int h, const std::uint8_t* colour) {
    for (int y = std::max(0, y0); y < std::min(image.height, y0 + h); ++y)
        for (int x = std::max(0, x0); x < std::min(image.width, x0 + w); ++x)
            std::copy(colour, colour + 3,
                      image.rgb.data() + (std::size_t(y) * std::size_t(image.width) + std::size_t(x)) * 3);
}

void drawLabel(MapImage& image, std::string_view label) {
    std::string digits;
    for (const char c : label)
        if (c >= '0' && c <= '9') digits += c;
    if (digits.empty()) return;
    const int advance = 4 * kFontScale;  // three pixels and a space
    const int box_w = int(digits.size()) * advance + kFontScale + 2 * kLabelMargin_px;
    const int box_h = 5 * kFontScale + 2 * kFontScale;
    fill(image, 0, 0, box_w, box_h, kMapBackground);
    for (std::size_t k = 0; k < digits.size(); ++k) {
        const std::uint8_t* rows = kDigits[digits[k] - '0'];
        for (int r = 0; r < 5; ++r)
            for (int c = 0; c < 3; ++c)
                if (rows[r] & (4 >> c))
                    fill(image, kLabelMargin_px + kFontScale + int(k) * advance + c * kFontScale,
                         kFontScale + r * kFontScale, kFontScale, kFontScale, kMapLabel);
    }
}

}  // namespace

MapImage renderErrorPanel(const std::vector<core::CloudPoint>& points, const std::vector<std::uint8_t>& truth,
                          const std::vector<std::uint8_t>& found, int side_px, std::string_view label) {
    if (truth.size() != points.size() || found.size() != points.size())
        throw core::Error("bench ground-isprs: error map: " + std::to_string(points.size()) + " points, " +
                          std::to_string(truth.size()) + " reference and " + std::to_string(found.size()) +
                          " found labels; allowed one of each per point");
    if (side_px < 16 || side_px > 8192)
        throw core::Error("bench ground-isprs: error map: panel side " + std::to_string(side_px) +
                          " px; allowed [16, 8192]");
    MapImage image{side_px, side_px, std::vector<std::uint8_t>(std::size_t(side_px) * std::size_t(side_px) * 3)};
    fill(image, 0, 0, side_px, side_px, kMapBackground);
    double x_lo = std::numeric_limits<double>::infinity(), y_lo = x_lo, x_hi = -x_lo, y_hi = -x_lo;
    for (const core::CloudPoint& p : points) {
        x_lo = std::min(x_lo, double(p.position.x)), x_hi = std::max(x_hi, double(p.position.x));
        y_lo = std::min(y_lo, double(p.position.y)), y_hi = std::max(y_hi, double(p.position.y));
    }
    if (!points.empty()) {
        // The larger extent spans the panel less a dot, so that every dot lies inside it.
        const int span_px = side_px - kErrorDot_px;
        const double extent = std::max({x_hi - x_lo, y_hi - y_lo, 1e-9});
        const double px_per_m = double(span_px) / extent;
        const double pad_x = 0.5 * (double(span_px) - (x_hi - x_lo) * px_per_m);
        const double pad_y = 0.5 * (double(span_px) - (y_hi - y_lo) * px_per_m);
        // Pass 0: the points the filter gets right; pass 1: its errors, over them.
        for (int pass = 0; pass < 2; ++pass)
            for (std::size_t k = 0; k < points.size(); ++k) {
                const bool wrong = (truth[k] != 0) != (found[k] != 0);
                if (wrong != (pass == 1)) continue;
                const int dot = wrong ? kErrorDot_px : kRightDot_px;
                const int x = int(std::lround(pad_x + (double(points[k].position.x) - x_lo) * px_per_m));
                const int y = int(std::lround(pad_y + (y_hi - double(points[k].position.y)) * px_per_m));
                const std::uint8_t* colour =
                    !wrong ? (truth[k] ? kMapGroundRight : kMapObjectRight) : (truth[k] ? kMapTypeI : kMapTypeII);
                fill(image, x, y, dot, dot, colour);
            }
    }
    drawLabel(image, label);
    return image;
}

MapImage mosaic(const std::vector<MapImage>& panels, int columns, int gap_px) {
    if (panels.empty() || columns < 1 || gap_px < 0)
        throw core::Error("bench ground-isprs: error map: " + std::to_string(panels.size()) + " panels in " +
                          std::to_string(columns) + " columns; allowed at least one in at least one");
    const int w = panels[0].width, h = panels[0].height;
    for (const MapImage& p : panels)
        if (p.width != w || p.height != h || p.rgb.size() != std::size_t(w) * std::size_t(h) * 3)
            throw core::Error("bench ground-isprs: error map: panels of different sizes; allowed one size");
    const int cols = std::min(columns, int(panels.size()));
    const int rows = (int(panels.size()) + cols - 1) / cols;
    MapImage out{cols * w + (cols + 1) * gap_px, rows * h + (rows + 1) * gap_px, {}};
    out.rgb.resize(std::size_t(out.width) * std::size_t(out.height) * 3);
    fill(out, 0, 0, out.width, out.height, kMapBackground);
    for (std::size_t k = 0; k < panels.size(); ++k) {
        const int x0 = gap_px + int(k % std::size_t(cols)) * (w + gap_px);
        const int y0 = gap_px + int(k / std::size_t(cols)) * (h + gap_px);
        if (gap_px > 0) fill(out, x0 - 1, y0 - 1, w + 2, h + 2, kMapFrame);  // a line around the panel
        for (int y = 0; y < h; ++y)
            std::copy(panels[k].at(0, y), panels[k].at(0, y) + std::size_t(w) * 3,
                      out.rgb.data() + (std::size_t(y0 + y) * std::size_t(out.width) + std::size_t(x0)) * 3);
    }
    return out;
}

}  // namespace bench
