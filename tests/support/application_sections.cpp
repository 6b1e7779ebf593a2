// Declares the mbd command's scene sections (`bench:`, `expect:`, app scene_sections.hpp) in
// every test program that links the application layer, so the tests load scenes/ as `mbd`
// does; the test support library itself needs the engine alone (tests/CMakeLists.txt). Support
// code, not a test: SceneSections.EveryTestProgramDeclaresTheApplicationsSections asserts it.
#include <mbd/app/scene_sections.hpp>

namespace {
[[maybe_unused]] const bool application_sections_declared = (mbd::declare_application_scene_sections(), true);
}  // namespace
