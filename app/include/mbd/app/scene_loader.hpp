// How a command that reads a scene by its path loads it: read_scene for mbd's YAML (with the
// declared application sections), or a loader the command line gives that also takes a model
// file (MJCF, URDF, SDF: mbd_import, which this library does not link; docs/import.md). An
// empty loader is read_scene.
#pragma once

#include <mbd/model.hpp>
#include <mbd/scene.hpp>
#include <mbd/registry.hpp>

#include <filesystem>
#include <functional>

namespace mbd {

using SceneLoader = std::function<Scene(const std::filesystem::path& file, Registry& registry)>;

// `load` when given, else read_scene.
Scene load_with(const SceneLoader& load, const std::filesystem::path& file, Registry& registry);

// The Scene of a model that has no application sections (a model file imported): its document
// is the model's.
Scene scene_of(Model model);

}  // namespace mbd
