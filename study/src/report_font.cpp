// study/src/report_font.cpp: the plots' font (report_font.hpp), taken from Dear ImGui's
// font atlas: ImFontAtlas builds its default font's glyphs into an alpha texture without
// any ImGui context or GL, and each ImFontGlyph gives the character's box in that texture
// (U0..V1) and its corners relative to the pen (X0..Y1).
#include "report_font.hpp"

#include <imgui.h>

#include <cmath>

namespace study::detail {

const FontGlyph& FontAtlas::glyph(char c) const {
    const unsigned char u = static_cast<unsigned char>(c);
    return glyphs[(u >= 32 && u <= 126) ? u - 32 : '?' - 32];
}

int FontAtlas::textWidth(std::string_view text) const {
    int w = 0;
    for (const char c : text) w += glyph(c).advance;
    return w;
}

namespace {
FontAtlas build() {
    ImFontAtlas atlas;
    ImFontConfig config;
    config.OversampleH = 1;
    config.OversampleV = 1;
    config.PixelSnapH = true;
    ImFont* font = atlas.AddFontDefault(&config);
    unsigned char* pixels = nullptr;
    int width = 0, height = 0;
    atlas.GetTexDataAsAlpha8(&pixels, &width, &height);
    FontAtlas out;
    out.width = width;
    out.height = height;
    out.coverage.assign(pixels, pixels + std::size_t(width) * std::size_t(height));
    out.line_height = int(std::lround(font->FontSize));
    for (int c = 32; c <= 126; ++c) {
        const ImFontGlyph* g = font->FindGlyph(static_cast<ImWchar>(c));
        FontGlyph& o = out.glyphs[std::size_t(c - 32)];
        o.advance = int(std::lround(g->AdvanceX));
        o.offset_x = int(std::lround(g->X0));
        o.offset_y = int(std::lround(g->Y0));
        o.atlas_x = int(std::lround(g->U0 * float(width)));
        o.atlas_y = int(std::lround(g->V0 * float(height)));
        o.width = int(std::lround((g->U1 - g->U0) * float(width)));
        o.height = int(std::lround((g->V1 - g->V0) * float(height)));
    }
    return out;
}
}  // namespace

const FontAtlas& reportFont() {
    static const FontAtlas font = build();
    return font;
}

}  // namespace study::detail
