// scene_sections.hpp.
#include <mbd/app/scene_sections.hpp>

#include <mbd/app/bench.hpp>
#include <mbd/app/stability.hpp>

namespace mbd {

std::vector<SceneSection> application_scene_sections() {
    return {{kBenchSection, "mbd bench (docs/scene-format.md, Benchmarks)"},
            {kExpectSection, "mbd stability (docs/stability.md, the declared outcome)"}};
}

void declare_application_scene_sections() { declare_scene_sections(application_scene_sections()); }

}  // namespace mbd
