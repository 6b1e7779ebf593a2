// The equilibrium as a scene: `mbd statics --output` writes it through OutputFile
// (output_file.hpp), and `mbd statics` on it starts at rest in equilibrium.
#pragma once

#include <mbd/model.hpp>

#include <string>

namespace mbd {

// The scene the model was loaded from (Model::document, `base:` files merged in) with every
// body's position/orientation replaced by `state`, its velocities removed (rest), and the
// joint (and world-frame force) points and axes moved with the bodies.
std::string equilibrium_scene(const Model& model, const State& state);

}  // namespace mbd
