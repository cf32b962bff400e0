// engine/src/text.hpp (internal): showing bytes from outside input in error messages.
// Every Error is one printable line (docs/scene.md), but tokens, names and parser
// messages quote what a file holds: control characters (a newline, an escape sequence
// for the terminal), DEL or binary bytes copied verbatim would break that line. Found by
// the libFuzzer targets (fuzz/, docs/stress.md).
#pragma once
#include <cstddef>
#include <cstdio>
#include <string>
#include <string_view>

namespace engine::detail {

/// `s` fit for an error message: control characters, DEL and (unless keep_utf8) every
/// byte >= 0x80 written as \xNN; at most `max_chars` characters of the RESULT, then
/// "..." (the cap is on what is shown, since escaping makes one byte four characters,
/// so a name of DEL bytes would otherwise overflow the message). With
/// keep_utf8, bytes >= 0x80 are kept (names from JSON, which nlohmann checks are UTF-8)
/// and the cut never splits a UTF-8 sequence.
inline std::string shown(std::string_view s, std::size_t max_chars = 40, bool keep_utf8 = false) {
    std::string out;
    out.reserve(s.size() < max_chars ? s.size() : max_chars + 3);
    std::size_t i = 0;
    while (i < s.size()) {
        const unsigned char c = static_cast<unsigned char>(s[i]);
        std::size_t used = 1;
        char piece[8];
        std::string_view view;
        if (c < 0x20 || c == 0x7f || (c >= 0x80 && !keep_utf8)) {
            std::snprintf(piece, sizeof piece, "\\x%02x", c);
            view = std::string_view(piece, 4);
        } else {
            while (keep_utf8 && c >= 0x80 && i + used < s.size() &&
                   (static_cast<unsigned char>(s[i + used]) & 0xC0) == 0x80)
                ++used;  // a whole UTF-8 sequence at once
            view = s.substr(i, used);
        }
        if (out.size() + view.size() > max_chars) {
            out += "...";
            return out;
        }
        out += view;
        i += used;
    }
    return out;
}

}  // namespace engine::detail
