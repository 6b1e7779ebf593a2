// How a command that reads a scene by its path loads it: load_scene for mbd's YAML, or a loader
// the command line gives that also takes a model file (MJCF, URDF, SDF: mbd_import, which this
// library does not link; docs/import.md). An empty loader is load_scene.
#pragma once

#include <mbd/model.hpp>
#include <mbd/registry.hpp>

#include <filesystem>
#include <functional>

namespace mbd {

using SceneLoader = std::function<Model(const std::filesystem::path& file, Registry& registry)>;

// `load` when given, else load_scene.
Model load_with(const SceneLoader& load, const std::filesystem::path& file, Registry& registry);

}  // namespace mbd
