// fuzz/fuzz_las_reader.cpp: libFuzzer target for the LAS/LAZ reader (io/src/las/
// las_reader.cpp, LASzip behind our header and VLR checks) through io::CloudReader,
// with the contract of fuzz_cloud_reader (check_cloud_reader.hpp). Every input is made to
// start with "LASF" so each mutation reaches the LAS reader, not the PCD one. Seeds:
// fuzz/seeds/las (make_seeds.py).
#include "check_cloud_reader.hpp"

#include <algorithm>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    std::string bytes(reinterpret_cast<const char*>(data), size);
    bytes.replace(0, std::min<std::size_t>(4, bytes.size()), "LASF");
    fuzz::checkCloudReader(bytes);
    return 0;
}
