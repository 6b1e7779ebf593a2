// The build's own paths, the one object of the tests compiled with them (MBD_TEST_PATH_*, from
// tests/CMakeLists.txt): every other test object is then the same in whichever folder the tree
// is built, so a compiler cache serves a fresh clone (CI's) from an earlier build.
#include "support/test_paths.hpp"

namespace mbd::test_paths {

const char* const source_dir = MBD_TEST_PATH_SOURCE_DIR;
const char* const build_dir = MBD_TEST_PATH_BUILD_DIR;
const char* const test_plugin_dir = MBD_TEST_PATH_PLUGIN_DIR;
const char* const executable = MBD_TEST_PATH_EXECUTABLE;

}  // namespace mbd::test_paths
