// The equilibrium as a scene: `mbd statics --output` writes it through OutputFile
// (output_file.hpp), and `mbd statics` on it starts at rest in equilibrium.
#pragma once

#include <mbd/model.hpp>
#include <mbd/scene.hpp>

#include <string>

namespace mbd {

// The scene as read (Scene::document, `base:` files merged in, application sections kept) with
// every body's position/orientation replaced by `state`, its velocities removed (rest), and the
// joint (and world-frame force) points and axes moved with the bodies.
std::string equilibrium_scene(const Scene& scene, const State& state);

}  // namespace mbd
