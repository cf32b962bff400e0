// viewer/src/ui/panel_layout.hpp: where the desktop mirror's windows go, as pure maths (no
// window, no ImGui): the settings panel's corner, size bounds and font scale, the picked
// point's panel beside (not over) the point, and the mode plate each eye image shows, so
// the panels can be kept inside the window and off the plate.
#pragma once

namespace viewer {

/// A rectangle in pixels from the top left (x right, y down).
struct PixelRect {
    float x = 0.0f, y = 0.0f, w = 0.0f, h = 0.0f;
    bool overlaps(const PixelRect& o) const { return x < o.x + o.w && o.x < x + w && y < o.y + o.h && o.y < y + h; }
    bool inside(float width, float height) const { return x >= 0.0f && y >= 0.0f && x + w <= width && y + h <= height; }
};

/// The mode plate ("AUTOMATIC", "FREE") of an eye image `eye_w` x `eye_h` pixels: centred
/// across, its top a fifth of the way down, in cells of at least one pixel (an eye's
/// three-hundredth), 6 cells a letter. In the image's pixels from its top left.
PixelRect modePlateRect(int eye_w, int eye_h, int letters);

/// The settings panel in a window of `width` x `height` pixels: anchored at its bottom left
/// corner (x, y), no wider than max_w nor taller than max_h (its lines wrap at max_w), in the
/// lower half, so it never reaches a mode plate (an eye image letterboxed in the window keeps
/// its plate above the middle) nor covers most of a small mirror; `compact` (small windows)
/// shows fewer lines in a smaller font.
struct SettingsPanelLayout {
    float x = 0.0f, y = 0.0f;  // the panel's bottom left corner
    float max_w = 0.0f, max_h = 0.0f;
    float font_scale = 1.0f;
    bool compact = false;
    PixelRect bound() const { return {x, y - max_h, max_w, max_h}; }
};
SettingsPanelLayout settingsPanelLayout(int width, int height);

/// The top left corner of the picked point's panel (`panel_w` x `panel_h`) for a point shown
/// at (`point_x`, `point_y`): beside it, at least a gap (a twentieth of the window's width,
/// 24 px at least) away on the side with room, vertically centred on it (in a window too
/// narrow for either side, below or above it), and moved inside the window when it would
/// cross an edge.
struct PanelPosition {
    float x = 0.0f, y = 0.0f;
};
PanelPosition pickPanelPosition(float point_x, float point_y, float panel_w, float panel_h, int width, int height);

}  // namespace viewer
