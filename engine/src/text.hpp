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
/// byte >= 0x80 written as \xNN; at most `max_bytes` of `s` shown, then "...". With
/// keep_utf8, bytes >= 0x80 are kept (names from JSON, which nlohmann checks are UTF-8)
/// and the cut never splits a UTF-8 sequence.
inline std::string shown(std::string_view s, std::size_t max_bytes = 40, bool keep_utf8 = false) {
    bool cut = false;
    if (s.size() > max_bytes) {
        std::size_t n = max_bytes;
        if (keep_utf8)
            while (n > 0 && (static_cast<unsigned char>(s[n]) & 0xC0) == 0x80) --n;
        s = s.substr(0, n);
        cut = true;
    }
    std::string out;
    out.reserve(s.size() + 3);
    for (const char ch : s) {
        const unsigned char c = static_cast<unsigned char>(ch);
        if (c < 0x20 || c == 0x7f || (c >= 0x80 && !keep_utf8)) {
            char hex[8];
            std::snprintf(hex, sizeof hex, "\\x%02x", c);
            out += hex;
        } else {
            out += ch;
        }
    }
    if (cut) out += "...";
    return out;
}

}  // namespace engine::detail
