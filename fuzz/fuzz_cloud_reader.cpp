// fuzz/fuzz_cloud_reader.cpp: libFuzzer target for engine::readCloudData (PCD ascii /
// binary / binary_compressed and PLY ascii / binary, chosen by content). The contract:
// whatever the bytes, the reader returns a cloud or throws engine::Error; it never reads
// outside the input, never crashes, never allocates more than the input can justify.
#include <engine/cloud_io.hpp>
#include <engine/error.hpp>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string_view>

namespace {

// The house rule for errors: one clear line. A message must hold no control character
// (a newline or an escape sequence copied from the input would break it), no byte from a binary file and stay short.
void checkMessage(const char* what) {
    std::size_t n = 0;
    for (const char* p = what; *p; ++p, ++n) {
        const unsigned char c = static_cast<unsigned char>(*p);
        if (c < 0x20 || c == 0x7f || c >= 0x80) {
            std::fprintf(stderr, "error message with byte 0x%02x at %zu: %s\n", c, n, what);
            std::abort();
        }
    }
    if (n > 1000) {
        std::fprintf(stderr, "error message of %zu bytes: %.200s...\n", n, what);
        std::abort();
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view bytes(reinterpret_cast<const char*>(data), size);
    try {
        const engine::PointCloud cloud = engine::readCloudData(bytes, "fuzz.pcd");
        // A cloud that was accepted must be usable: labels in range, origin finite.
        for (const engine::CloudPoint& p : cloud.points)
            if (static_cast<int>(p.label) > 2) std::abort();
        if (!std::isfinite(cloud.origin.x) || !std::isfinite(cloud.origin.y) || !std::isfinite(cloud.origin.z))
            std::abort();
    } catch (const engine::Error& e) {
        checkMessage(e.what());
        // The documented way to refuse bad input. LADARVR_FUZZ_VERBOSE=1 shows why (seeds).
        if (std::getenv("LADARVR_FUZZ_VERBOSE")) std::fprintf(stderr, "refused: %s\n", e.what());
    }
    return 0;
}
