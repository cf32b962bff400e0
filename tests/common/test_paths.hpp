// tests/common/test_paths.hpp: where the tests find the checkout's files and the CLI.
#pragma once

namespace test_support {

// Each is an absolute path of this build's checkout. They are compiled into one file of
// test_main (test_paths.cpp) only, so no other test object names the checkout's folder
// and ccache shares those objects between clones.

/// tests/data
const char* dataDir();
/// assets
const char* assetsDir();
/// tests/data/isprs: the ISPRS filter-test samples
const char* isprsDir();
/// tests/data/real: the small real surveys
const char* realDataDir();
/// tests/corpus/data
const char* corpusDataDir();
/// fuzz/seeds: the fuzz targets' seeds, one folder per target
const char* fuzzSeedsDir();
/// shaders
const char* shadersDir();
/// The `ladarvr` CLI of this build.
const char* cliPath();

}  // namespace test_support
