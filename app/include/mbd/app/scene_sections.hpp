// The mbd command's own scene keys (core scene.hpp SceneSection): the top-level sections its
// applications read from a scene file beside the physics. The core names none of them.
#pragma once

#include <mbd/scene.hpp>

#include <vector>

namespace mbd {

// `bench:` (mbd bench, bench_spec.cpp) and `expect:` (mbd stability, stability.cpp).
std::vector<SceneSection> application_scene_sections();

// Declares them for every scene load in this process (declare_scene_sections): the mbd
// command, the Python module and the tests call it once at their start.
void declare_application_scene_sections();

}  // namespace mbd
