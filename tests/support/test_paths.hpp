// The build's paths for the tests: the source tree, the build tree, the test-only plugins and
// the mbd executable (defined in test_paths.cpp). The macros MBD_SOURCE_DIR, MBD_BUILD_DIR,
// MBD_TEST_PLUGIN_DIR and MBD_EXECUTABLE name these (const char*); test_support.hpp includes
// this header.
#pragma once

namespace mbd::test_paths {

extern const char* const source_dir;
extern const char* const build_dir;
extern const char* const test_plugin_dir;
extern const char* const executable;

}  // namespace mbd::test_paths
