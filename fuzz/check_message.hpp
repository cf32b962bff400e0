// fuzz/check_message.hpp: the house rule for errors, checked by every fuzz target on
// every message it provokes: one short line, no control character (a newline or an
// escape sequence copied from the input would break it) and, with `ascii_only`, no byte
// >= 0x80 either (for parsers of binary files). A breach aborts, so libFuzzer keeps it.
#pragma once
#include <cstddef>
#include <cstdio>
#include <cstdlib>

namespace fuzz {

inline void checkMessage(const char* what, bool ascii_only = false) {
    std::size_t n = 0;
    for (const char* p = what; *p; ++p, ++n) {
        const unsigned char c = static_cast<unsigned char>(*p);
        if (c < 0x20 || c == 0x7f || (ascii_only && c >= 0x80)) {
            std::fprintf(stderr, "error message with byte 0x%02x at %zu: %s\n", c, n, what);
            std::abort();
        }
    }
    if (n > 1000) {
        std::fprintf(stderr, "error message of %zu bytes: %.200s...\n", n, what);
        std::abort();
    }
}

}  // namespace fuzz
