// An ImportedScene as the text of an mbd scene file (docs/scene-format.md): readable YAML, each
// body, joint and force preceded by a comment naming the source element it came from (its file,
// and line where the parser gives one), every number with 17 significant digits so that the
// scene reproduces the model exactly.
#pragma once

#include <mbd/import/imported_scene.hpp>

#include <string>

namespace mbd::import {

std::string scene_yaml(const ImportedScene& scene);

}  // namespace mbd::import
