// study/src/report_plot.cpp: the report's PNG plots (report_plot.hpp).
#include "report_plot.hpp"

#include "report_font.hpp"

#include <io/png.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace study::detail {

namespace {
using Colour = Canvas::Colour;
constexpr Colour kInk{30, 30, 30, 255};
constexpr Colour kGrid{225, 225, 225, 255};
constexpr Colour kDot{110, 110, 110, 170};
constexpr Colour kBar{70, 130, 180, 255};
constexpr Colour kWhisker{20, 40, 90, 255};
constexpr int kWidth = 720, kHeight = 420;
constexpr int kLeft = 80, kRight = 24, kTop = 58, kBottom = 64;

std::string tickLabel(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.4g", std::fabs(v) < 1e-12 ? 0.0 : v);
    return buf;
}

// Ticks at 1, 2 or 5 times a power of ten, about five over [lo, hi].
std::vector<double> ticks(double lo, double hi) {
    const double raw = (hi - lo) / 5.0;
    const double magnitude = std::pow(10.0, std::floor(std::log10(raw)));
    double step = magnitude;
    for (const double m : {1.0, 2.0, 5.0, 10.0})
        if (m * magnitude >= raw) {
            step = m * magnitude;
            break;
        }
    std::vector<double> out;
    for (double t = std::ceil(lo / step - 1e-9) * step; t <= hi + step * 1e-9 && out.size() < 20; t += step)
        out.push_back(t);
    return out;
}

// The frame of a plot: title, the y axis from lo to hi with grid lines and labels.
struct Frame {
    Canvas canvas{kWidth, kHeight};
    double lo = 0.0, hi = 1.0;
    int x0 = kLeft, x1 = kWidth - kRight, y0 = kTop, y1 = kHeight - kBottom;  // plot area

    int y(double v) const { return int(std::lround(y1 - (v - lo) / (hi - lo) * (y1 - y0))); }

    void draw(std::string_view title, std::string_view axis_label) {
        canvas.text(kLeft, 10, title, kInk, 2);
        canvas.text(8, kTop - 18, axis_label, kInk);
        for (const double t : ticks(lo, hi)) {
            const int ty = y(t);
            canvas.fillRect(x0, ty, x1, ty + 1, kGrid);
            const std::string label = tickLabel(t);
            canvas.fillRect(x0 - 5, ty, x0, ty + 1, kInk);
            canvas.text(x0 - 8 - Canvas::textWidth(label), ty - Canvas::lineHeight() / 2, label, kInk);
        }
        canvas.fillRect(x0, y0, x0 + 1, y1 + 1, kInk);
        canvas.fillRect(x0, y1, x1, y1 + 1, kInk);
    }
};
}  // namespace

Canvas::Canvas(int width, int height)
    : width_(width), height_(height), rgba_(std::size_t(width) * std::size_t(height) * 4, 255) {}

Canvas::Colour Canvas::pixel(int x, int y) const {
    if (x < 0 || y < 0 || x >= width_ || y >= height_) return {0, 0, 0, 0};
    const std::uint8_t* p = &rgba_[(std::size_t(y) * std::size_t(width_) + std::size_t(x)) * 4];
    return {p[0], p[1], p[2], p[3]};
}

void Canvas::blend(int x, int y, Colour c, double coverage) {
    if (x < 0 || y < 0 || x >= width_ || y >= height_) return;
    const double a = std::clamp(coverage, 0.0, 1.0) * c.a / 255.0;
    std::uint8_t* p = &rgba_[(std::size_t(y) * std::size_t(width_) + std::size_t(x)) * 4];
    p[0] = std::uint8_t(std::lround(p[0] * (1.0 - a) + c.r * a));
    p[1] = std::uint8_t(std::lround(p[1] * (1.0 - a) + c.g * a));
    p[2] = std::uint8_t(std::lround(p[2] * (1.0 - a) + c.b * a));
    p[3] = 255;
}

void Canvas::fillRect(int x0, int y0, int x1, int y1, Colour c) {
    for (int y = std::max(0, y0); y < std::min(height_, y1); ++y)
        for (int x = std::max(0, x0); x < std::min(width_, x1); ++x) blend(x, y, c, 1.0);
}

void Canvas::disc(double cx, double cy, double r, Colour c) {
    for (int y = int(std::floor(cy - r - 1)); y <= int(std::ceil(cy + r + 1)); ++y)
        for (int x = int(std::floor(cx - r - 1)); x <= int(std::ceil(cx + r + 1)); ++x) {
            // Coverage from the distance of the pixel's centre to the edge: smooth rims.
            const double d = std::hypot(x + 0.5 - cx, y + 0.5 - cy);
            if (d < r + 0.5) blend(x, y, c, r + 0.5 - d);
        }
}

void Canvas::text(int x, int y, std::string_view s, Colour c, int scale) {
    const FontAtlas& font = reportFont();
    int pen = x;
    for (const char ch : s) {
        const FontGlyph& g = font.glyph(ch);
        for (int gy = 0; gy < g.height; ++gy)
            for (int gx = 0; gx < g.width; ++gx) {
                const std::uint8_t v =
                    font.coverage[std::size_t(g.atlas_y + gy) * std::size_t(font.width) + std::size_t(g.atlas_x + gx)];
                if (v == 0) continue;
                for (int sy = 0; sy < scale; ++sy)
                    for (int sx = 0; sx < scale; ++sx)
                        blend(pen + (g.offset_x + gx) * scale + sx, y + (g.offset_y + gy) * scale + sy, c, v / 255.0);
            }
        pen += g.advance * scale;
    }
}

int Canvas::textWidth(std::string_view s, int scale) { return reportFont().textWidth(s) * scale; }
int Canvas::lineHeight(int scale) { return reportFont().line_height * scale; }

std::string Canvas::png() const {
    std::vector<std::uint8_t> rgb(std::size_t(width_) * std::size_t(height_) * 3);
    for (std::size_t i = 0, n = std::size_t(width_) * std::size_t(height_); i < n; ++i)
        for (std::size_t k = 0; k < 3; ++k) rgb[i * 3 + k] = rgba_[i * 4 + k];
    return io::encodePng(rgb, width_, height_, 3);
}

std::string conditionPlotPng(std::string_view title, std::string_view axis_label,
                             const std::vector<std::string>& conditions, const std::vector<std::vector<double>>& values,
                             const std::vector<stats::Summary>& summaries, bool unit_range) {
    Frame f;
    if (!unit_range) {
        double top = 0.0;
        for (const auto& row : values)
            for (const double v : row)
                if (!std::isnan(v)) top = std::max(top, v);
        for (const stats::Summary& s : summaries)
            if (!std::isnan(s.ci95_high)) top = std::max(top, s.ci95_high);
        f.hi = top > 0.0 ? top * 1.1 : 1.0;
    }
    f.draw(title, axis_label);
    const std::size_t k = std::max<std::size_t>(1, conditions.size());
    const double band = double(f.x1 - f.x0) / double(k);
    for (std::size_t j = 0; j < conditions.size(); ++j) {
        const double centre = f.x0 + band * (double(j) + 0.5);
        const int name_w = Canvas::textWidth(conditions[j]);
        f.canvas.text(int(centre) - name_w / 2, f.y1 + 10, conditions[j], kInk);
        const stats::Summary& s = summaries[j];
        const std::string n_label = "n = " + std::to_string(s.n);
        f.canvas.text(int(centre) - Canvas::textWidth(n_label) / 2, f.y1 + 28, n_label, kInk);
        const double half = std::min(40.0, band * 0.25);
        if (!std::isnan(s.mean)) {
            f.canvas.fillRect(int(centre - half), std::min(f.y(s.mean), f.y(0.0)), int(centre + half),
                              std::max(f.y(s.mean), f.y(0.0)) + 1, Colour{kBar.r, kBar.g, kBar.b, 110});
            f.canvas.fillRect(int(centre - half), f.y(s.mean) - 1, int(centre + half), f.y(s.mean) + 2, kBar);
        }
        if (!std::isnan(s.ci95_low)) {
            const int top = f.y(std::min(s.ci95_high, f.hi)), bottom = f.y(std::max(s.ci95_low, f.lo));
            f.canvas.fillRect(int(centre) - 1, top, int(centre) + 2, bottom + 1, kWhisker);
            f.canvas.fillRect(int(centre - half / 2), top - 1, int(centre + half / 2), top + 2, kWhisker);
            f.canvas.fillRect(int(centre - half / 2), bottom - 1, int(centre + half / 2), bottom + 2, kWhisker);
        }
        // Participants' dots spread across the band so equal values stay visible.
        for (std::size_t p = 0; p < values.size(); ++p) {
            if (j >= values[p].size() || std::isnan(values[p][j])) continue;
            const double spread = values.size() > 1 ? (double(p) / double(values.size() - 1) - 0.5) : 0.0;
            f.canvas.disc(centre + spread * half * 1.6, f.y(values[p][j]), 3.0, kDot);
        }
    }
    if (conditions.empty()) f.canvas.text(f.x0 + 20, f.y0 + 20, "no conditions", kInk);
    return f.canvas.png();
}

std::string cloudPlotPng(const std::vector<CloudFigures>& clouds) {
    Frame f;
    f.draw("Hit rate per cloud vs visibility", "hit rate (per cloud)");
    for (const double t : ticks(0.0, 1.0)) {
        const int tx = int(std::lround(f.x0 + t * (f.x1 - f.x0)));
        f.canvas.fillRect(tx, f.y0, tx + 1, f.y1, kGrid);
        f.canvas.fillRect(tx, f.y1, tx + 1, f.y1 + 5, kInk);
        const std::string label = tickLabel(t);
        f.canvas.text(tx - Canvas::textWidth(label) / 2, f.y1 + 8, label, kInk);
    }
    const std::string x_label = "visibility metric (trials.csv)";
    f.canvas.text((f.x0 + f.x1 - Canvas::textWidth(x_label)) / 2, f.y1 + 28, x_label, kInk);
    std::size_t shown = 0;
    for (const CloudFigures& c : clouds) {
        if (std::isnan(c.visibility_metric) || std::isnan(c.all.hit_rate)) continue;
        ++shown;
        f.canvas.disc(f.x0 + c.visibility_metric * (f.x1 - f.x0), f.y(c.all.hit_rate), 4.5, kBar);
    }
    const std::string note = std::to_string(shown) + " of " + std::to_string(clouds.size()) +
                             " clouds shown (the others have no visibility metric or no scored trial)";
    f.canvas.text(f.x0, f.y1 + 46, note, kInk);
    return f.canvas.png();
}

}  // namespace study::detail
