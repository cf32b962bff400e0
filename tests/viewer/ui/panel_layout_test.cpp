// tests/viewer/ui/panel_layout_test.cpp: where the mirror's panels go (no window): inside the
// window, off the mode plate of every eye image the mirror shows, not over most of a small
// mirror, and the picked point's panel beside the point, not over it.
#include "ui/panel_layout.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <vector>

using namespace viewer;

namespace {
// An eye image of img_w x img_h letterboxed into an area of the window, as the mirror
// shows it (aspect kept, centred), and its mode plate in window pixels.
PixelRect plateInWindow(float area_x, float area_w, float area_h, int img_w, int img_h, int letters) {
    const float s = std::min(area_w / float(img_w), area_h / float(img_h));
    const float x0 = area_x + (area_w - float(img_w) * s) / 2.0f, y0 = (area_h - float(img_h) * s) / 2.0f;
    const PixelRect p = modePlateRect(img_w, img_h, letters);
    return {x0 + p.x * s, y0 + p.y * s, p.w * s, p.h * s};
}

// Every plate of "AUTOMATIC" (9 letters) and "FREE" the mirror shows: both eyes side by
// side, the left eye alone, or the desktop view (the window itself).
std::vector<PixelRect> plates(int width, int height, int eye_w, int eye_h) {
    std::vector<PixelRect> out;
    for (int letters : {9, 4}) {
        out.push_back(plateInWindow(0.0f, float(width) / 2, float(height), eye_w, eye_h, letters));
        out.push_back(plateInWindow(float(width) / 2, float(width) / 2, float(height), eye_w, eye_h, letters));
        out.push_back(plateInWindow(0.0f, float(width), float(height), eye_w, eye_h, letters));
        out.push_back(plateInWindow(0.0f, float(width), float(height), width, height, letters));
    }
    return out;
}
}  // namespace

TEST_CASE("the mode plate is centred across an eye image, a fifth of the way down") {
    const PixelRect p = modePlateRect(1000, 900, 9);
    CHECK(p.w == 55.0f * 3.0f);  // 9 letters of 6 cells and one, cells of 900 / 300 px
    CHECK(p.h == 27.0f);
    CHECK(p.x == 417.0f);
    CHECK(p.y == 180.0f);
    CHECK(modePlateRect(200, 100, 4).h == 9.0f);  // a cell is one pixel at least
}

TEST_CASE("the settings panel stays inside the window and off every eye's mode plate") {
    // Window sizes the mirror is opened at, and eye images of a headset and of Monado's
    // simulated one.
    for (const auto& [w, h] : std::vector<std::pair<int, int>>{
             {1280, 720}, {960, 540}, {640, 480}, {320, 240}, {1920, 1080}, {960, 240}, {400, 900}})
        for (const auto& [ew, eh] : std::vector<std::pair<int, int>>{{1440, 1600}, {2000, 2000}, {1280, 720}}) {
            CAPTURE(w);
            CAPTURE(h);
            CAPTURE(ew);
            CAPTURE(eh);
            const SettingsPanelLayout l = settingsPanelLayout(w, h);
            CHECK(l.bound().inside(float(w), float(h)));
            for (const PixelRect& p : plates(w, h, ew, eh)) CHECK_FALSE(l.bound().overlaps(p));
        }
}

TEST_CASE("on a small mirror the settings panel is compact and covers at most a quarter of the view") {
    const SettingsPanelLayout small = settingsPanelLayout(320, 240);
    CHECK(small.compact);
    CHECK(small.font_scale < 1.0f);
    CHECK(small.max_w * small.max_h <= 0.25f * 320.0f * 240.0f);
    const SettingsPanelLayout large = settingsPanelLayout(1280, 720);
    CHECK_FALSE(large.compact);
    CHECK(large.font_scale == 1.0f);
}

TEST_CASE("the picked point's panel is beside the point, never over it, and inside the window") {
    const float pw = 180.0f, ph = 60.0f;
    for (const auto& [w, h] : std::vector<std::pair<int, int>>{{960, 540}, {320, 240}, {1280, 720}})
        for (float fx : {0.02f, 0.3f, 0.5f, 0.7f, 0.98f})
            for (float fy : {0.02f, 0.5f, 0.98f}) {
                const float x = fx * float(w), y = fy * float(h);
                CAPTURE(w);
                CAPTURE(x);
                CAPTURE(y);
                const PanelPosition p = pickPanelPosition(x, y, pw, ph, w, h);
                const PixelRect panel{p.x, p.y, pw, ph};
                CHECK(panel.inside(float(w), float(h)));
                // The target around the point (a square of 16 px either side) stays clear.
                CHECK_FALSE(panel.overlaps({x - 16.0f, y - 16.0f, 32.0f, 32.0f}));
            }
    // On the right when there is room, vertically centred on the point.
    const PanelPosition p = pickPanelPosition(300.0f, 270.0f, pw, ph, 960, 540);
    CHECK(p.x >= 300.0f + 24.0f);
    CHECK(p.y == doctest::Approx(240.0f));
}
