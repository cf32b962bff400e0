// viewer/src/ui/panel_layout.cpp: the mirror's panel placement maths.
#include "ui/panel_layout.hpp"

#include <algorithm>
#include <cmath>

namespace viewer {

namespace {
constexpr float kMargin_px = 10.0f;  // between a panel and the window's edge
}  // namespace

PixelRect modePlateRect(int eye_w, int eye_h, int letters) {
    const float w = float(eye_w), h = float(eye_h);
    const float cell = std::max(1.0f, std::floor(h / 300.0f));
    PixelRect r;
    r.w = float(letters * 6 + 1) * cell;
    r.h = 9.0f * cell;
    r.x = std::floor((w - r.w) / 2.0f);
    r.y = std::floor(h * 0.2f);
    return r;
}

SettingsPanelLayout settingsPanelLayout(int width, int height) {
    const float w = float(std::max(width, 1)), h = float(std::max(height, 1));
    SettingsPanelLayout l;
    l.compact = width < 640 || height < 400;
    // ImGui's 13 px font: full size from 540 px high, never under 0.7 (still readable).
    l.font_scale = std::clamp(h / 540.0f, 0.7f, 1.0f);
    l.x = std::min(kMargin_px, w * 0.02f);
    l.y = h - std::min(kMargin_px, h * 0.02f);
    // The lower half (less its margin); compact panels also keep to half the width, so
    // at most a quarter of a small mirror is covered.
    l.max_h = std::max(1.0f, h * 0.5f - (h - l.y));
    l.max_w = std::max(1.0f, (l.compact ? w * 0.5f : std::min(w * 0.6f, 520.0f)) - l.x);
    return l;
}

PanelPosition pickPanelPosition(float point_x, float point_y, float panel_w, float panel_h, int width, int height) {
    const float w = float(width), h = float(height);
    const float gap = std::max(24.0f, w / 20.0f);
    PanelPosition p;
    // The right side when it has room, else the left; in a window too narrow for either,
    // below the point when there is room, else above it.
    const bool fits_right = point_x + gap + panel_w <= w - kMargin_px;
    const bool fits_left = point_x - gap - panel_w >= kMargin_px;
    if (fits_right || fits_left) {
        p.x = fits_right ? point_x + gap : point_x - gap - panel_w;
        p.y = point_y - panel_h * 0.5f;
    } else {
        p.x = point_x - panel_w * 0.5f;
        p.y = point_y + gap + panel_h <= h - kMargin_px ? point_y + gap : point_y - gap - panel_h;
    }
    // Inside the window (the left and top edges win when it is larger than the window).
    p.x = std::max(std::min(p.x, w - kMargin_px - panel_w), std::min(kMargin_px, w * 0.02f));
    p.y = std::max(std::min(p.y, h - kMargin_px - panel_h), std::min(kMargin_px, h * 0.02f));
    return p;
}

}  // namespace viewer
