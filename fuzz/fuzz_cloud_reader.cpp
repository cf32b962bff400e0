// fuzz/fuzz_cloud_reader.cpp: libFuzzer target for io::CloudReader over bytes in
// memory (PCD ascii / binary / binary_compressed and PLY ascii / binary, chosen by
// content), whole (readCloudData) and chunk by chunk (nextChunk, the viewer's path).
// The contract: whatever the bytes, the reader returns a cloud or throws core::Error;
// it never reads outside the input, never crashes, never allocates more than the input
// can justify; every point it returns is finite with a label in 0..2; reading in
// chunks of any size gives exactly the whole read's points, or the same error; and a
// cloud read whole also reads with a foreign file's side records kept (one per point)
// and positions only, to the same points.
#include "check_cloud_reader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    fuzz::checkCloudReader(std::string_view(reinterpret_cast<const char*>(data), size));
    return 0;
}
