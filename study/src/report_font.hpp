// study/src/report_font.hpp: the text of the report's plots: Dear ImGui's default font
// (ProggyClean, 13 pixels) rasterised once on the CPU into an 8-bit coverage atlas, so the
// plots need neither a GL context nor a font file. Printable ASCII only; any other byte is
// drawn as '?'.
#pragma once
#include <array>
#include <cstdint>
#include <string_view>
#include <vector>

namespace study::detail {

/// One character's box in the atlas and where it sits relative to the pen (the pen at the
/// top-left of the line).
struct FontGlyph {
    int atlas_x = 0, atlas_y = 0, width = 0, height = 0;
    int offset_x = 0, offset_y = 0;
    int advance = 0;
};

struct FontAtlas {
    int width = 0, height = 0;
    std::vector<std::uint8_t> coverage;  // width * height, 0 = empty, 255 = ink
    int line_height = 0;
    std::array<FontGlyph, 95> glyphs{};  // ' ' (32) to '~' (126)

    /// The glyph of `c` ('?' for bytes outside printable ASCII).
    const FontGlyph& glyph(char c) const;
    /// The width of `text` in pixels at scale 1.
    int textWidth(std::string_view text) const;
};

/// The atlas, built on first use (thread-safe) and kept for the process.
const FontAtlas& reportFont();

}  // namespace study::detail
