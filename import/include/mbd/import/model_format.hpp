// Which kind of file a model or scene file is, from its content (not its name): an XML file is
// known by its root element (<mujoco>: MJCF, <robot>: URDF, <sdf>: SDF); anything else is taken
// for an mbd scene (YAML).
#pragma once

#include <filesystem>
#include <string>

namespace mbd::import {

enum class ModelFormat { Scene, Mjcf, Urdf, Sdf };

// Throws InputError for an XML file of another root element; a file that is not a readable
// regular file is reported as a Scene (the scene loader then says why it cannot read it).
ModelFormat detect_format(const std::filesystem::path& file);

std::string format_name(ModelFormat format);

}  // namespace mbd::import
