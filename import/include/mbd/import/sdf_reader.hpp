// SDF through libsdformat (Debian libsdformat-dev, sdformat 12), Gazebo's own parser: it checks
// the file against the SDF specification, builds the frame graphs and resolves every pose and
// axis (`relative_to`, `expressed_in`, SDF 1.4-1.6's `use_parent_model_frame`) itself; mbd only
// composes the resolved poses with the model's placement in the world.
#pragma once

#include <mbd/import/source_tree.hpp>

#include <filesystem>

namespace mbd::import {

// Throws InputError with libsdformat's message and file:line when the file does not load, and
// naming the element for a joint type mbd cannot map or links that no tree reaches.
SourceTree read_sdf(const std::filesystem::path& file);

}  // namespace mbd::import
