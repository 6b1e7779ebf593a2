// Scene files (YAML): the format is documented in docs/scene-format.md.
#pragma once

#include <mbd/model.hpp>
#include <mbd/registry.hpp>

#include <filesystem>
#include <string>

namespace mbd {

// Load a scene, creating its joints and forces through the registry (only the
// libraries the scene uses are opened). Throws InputError with file:line.
Model load_scene(const std::filesystem::path& file, Registry& registry);
Model load_scene_text(const std::string& yaml, const std::string& label, Registry& registry);

}  // namespace mbd
