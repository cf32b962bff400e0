// study/src/csv_cell.cpp: text cells of the study's CSV files (study/csv_cell.hpp).
#include <study/csv_cell.hpp>

#include <cstdio>

namespace study {

namespace {

// The code point of the valid UTF-8 sequence at text[i] and its length in `n`; n = 0
// when text[i] does not start one (a stray continuation byte, an overlong form, a
// surrogate, past U+10FFFF, or cut short).
char32_t decodeUtf8(std::string_view text, std::size_t i, std::size_t& n) {
    const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(text[k]); };
    const unsigned char c = byte(i);
    n = 0;
    if (c < 0x80) {
        n = 1;
        return c;
    }
    std::size_t len = 0;
    char32_t cp = 0, min = 0;
    if ((c & 0xE0) == 0xC0) {
        len = 2, cp = c & 0x1F, min = 0x80;
    } else if ((c & 0xF0) == 0xE0) {
        len = 3, cp = c & 0x0F, min = 0x800;
    } else if ((c & 0xF8) == 0xF0) {
        len = 4, cp = c & 0x07, min = 0x10000;
    } else {
        return 0;
    }
    if (i + len > text.size()) return 0;
    for (std::size_t k = 1; k < len; ++k) {
        if ((byte(i + k) & 0xC0) != 0x80) return 0;
        cp = (cp << 6) | (byte(i + k) & 0x3F);
    }
    if (cp < min || cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF)) return 0;
    n = len;
    return cp;
}

bool bidiControl(char32_t cp) {
    return cp == 0x200E || cp == 0x200F || (cp >= 0x202A && cp <= 0x202E) || (cp >= 0x2066 && cp <= 0x2069);
}

std::string escape(const char* format, unsigned value) {
    char buf[12];
    std::snprintf(buf, sizeof buf, format, value);
    return buf;
}

}  // namespace

std::string escapeControlText(std::string_view text) {
    std::string out;
    out.reserve(text.size());
    for (std::size_t i = 0; i < text.size();) {
        std::size_t n = 0;
        const char32_t cp = decodeUtf8(text, i, n);
        if (n == 0) {
            out += escape("\\x%02x", static_cast<unsigned char>(text[i]));
            ++i;
            continue;
        }
        if (cp < 0x20 || cp == 0x7F)
            out += escape("\\x%02x", unsigned(cp));
        else if ((cp >= 0x80 && cp <= 0x9F) || bidiControl(cp))
            out += escape("\\u%04x", unsigned(cp));
        else
            out.append(text.substr(i, n));
        i += n;
    }
    return out;
}

std::string csvSafeText(std::string_view text) {
    std::string out = escapeControlText(text);
    // OWASP's list also names a leading tab and carriage return: escaped above already.
    if (!out.empty() && (out[0] == '=' || out[0] == '+' || out[0] == '-' || out[0] == '@'))
        out.insert(out.begin(), '\'');
    return out;
}

std::string csvCell(std::string_view text) {
    std::string safe = csvSafeText(text);
    if (safe.find_first_of(",\"") == std::string::npos) return safe;
    std::string out = "\"";
    for (const char c : safe) out += c == '"' ? std::string("\"\"") : std::string(1, c);
    return out + "\"";
}

}  // namespace study
