// engine.hpp: the version the library was built as (the project's version, CMakeLists.txt).
#include <mbd/engine.hpp>

namespace mbd {

const char* engine_version() { return MBD_VERSION; }

}  // namespace mbd
