// core/error.hpp: the project's one error type for bad input or configuration.
#pragma once
#include <cstddef>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <string_view>

namespace core {

/// Thrown for bad input, configuration or environment. The message is one line that
/// starts with the module ("scene: ", "orbit: ", "pcd: ", ...) and names the offending
/// file, field or parameter and what is allowed. `main` prints it and exits non-zero.
class Error : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

/// A number as messages show it: "%.<digits>g", so 1e308 reads "1e+308" (not 309
/// digits), 0.2 reads "0.2" and, with the default 10 digits, limits such as 1048576 keep
/// every digit. Values read as floats from files are shown with 6 (printf's "%g"), so
/// float noise does not show (1.1f reads "1.1", not "1.100000024").
inline std::string shownNumber(double v, int digits = 10) {
    char buffer[48];
    std::snprintf(buffer, sizeof buffer, "%.*g", digits, v);
    return buffer;
}

/// `s` fit for a one-line message (every Error is one printable line, but tokens, names
/// and parser messages quote what outside files hold; control characters or binary bytes
/// copied verbatim would break that line): control characters, DEL and (unless keep_utf8) every
/// byte >= 0x80 written as \xNN; at most `max_chars` characters of the RESULT, then
/// "..." (the cap is on what is shown, since escaping makes one byte four characters,
/// so a name of DEL bytes would otherwise overflow the message). With
/// keep_utf8, bytes >= 0x80 are kept (names from JSON, which nlohmann checks are UTF-8)
/// and the cut never splits a UTF-8 sequence.
inline std::string printable(std::string_view s, std::size_t max_chars = 200, bool keep_utf8 = false) {
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

}  // namespace core
