// study/src/report_plot.hpp: the report's plots as PNG file images, drawn by our own code
// into an RGBA canvas (filled rectangles, discs and the text of report_font.hpp) and
// encoded by io::encodePng.
#pragma once
#include <study/report.hpp>

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace study::detail {

/// An RGBA image, top row first, opaque white to begin with; every draw blends its colour
/// with the given opacity and clips to the image.
class Canvas {
  public:
    struct Colour {
        std::uint8_t r = 0, g = 0, b = 0, a = 255;
    };
    Canvas(int width, int height);
    int width() const { return width_; }
    int height() const { return height_; }
    /// The pixel at (x, y), or transparent black outside.
    Colour pixel(int x, int y) const;
    /// Fills [x0, x1) x [y0, y1).
    void fillRect(int x0, int y0, int x1, int y1, Colour c);
    /// A filled disc of radius `r` pixels around (cx, cy).
    void disc(double cx, double cy, double r, Colour c);
    /// `text` with its top-left corner at (x, y), every pixel of the font `scale` x `scale`.
    void text(int x, int y, std::string_view text, Colour c, int scale = 1);
    /// The width of `text` in pixels at `scale`.
    static int textWidth(std::string_view text, int scale = 1);
    static int lineHeight(int scale = 1);
    /// The PNG file image (RGB: the canvas is opaque).
    std::string png() const;

  private:
    void blend(int x, int y, Colour c, double coverage);
    int width_, height_;
    std::vector<std::uint8_t> rgba_;
};

/// A measure per condition: each participant's value as a small grey dot, the mean as a
/// bar and its 95 % confidence interval as whiskers. `values[p][c]` is NaN where a
/// participant has none; `unit_range` fixes the axis to [0, 1] (rates).
std::string conditionPlotPng(std::string_view title, std::string_view axis_label,
                             const std::vector<std::string>& conditions, const std::vector<std::vector<double>>& values,
                             const std::vector<stats::Summary>& summaries, bool unit_range);

/// Each cloud's hit rate against its visibility metric (both in [0, 1]); clouds without a
/// metric or without scored trials are left out, and the plot says how many.
std::string cloudPlotPng(const std::vector<CloudFigures>& clouds);

}  // namespace study::detail
