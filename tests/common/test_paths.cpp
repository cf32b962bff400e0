// tests/common/test_paths.cpp: the paths of test_paths.hpp, from the build's definitions.
#include "test_paths.hpp"

namespace test_support {

const char* dataDir() { return LADARVR_TEST_SOURCE_DIR "/data"; }
const char* assetsDir() { return LADARVR_ASSETS_DIR; }
const char* isprsDir() { return LADARVR_TEST_SOURCE_DIR "/data/isprs"; }
const char* realDataDir() { return LADARVR_TEST_SOURCE_DIR "/data/real"; }
const char* corpusDataDir() { return LADARVR_TEST_SOURCE_DIR "/corpus/data"; }
const char* fuzzSeedsDir() { return LADARVR_TEST_SOURCE_DIR "/../fuzz/seeds"; }
const char* shadersDir() { return LADARVR_SHADERS_DIR; }
const char* cliPath() { return LADARVR_CLI; }

}  // namespace test_support
