// Scene files (YAML): the format is documented in docs/scene-format.md.
#pragma once

#include <mbd/model.hpp>
#include <mbd/registry.hpp>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>

namespace mbd {

// What the scene reader accepts at most (docs/scene-format.md, "Limits"). Beyond these a
// scene is refused with file:line before it can exhaust memory or the stack: the YAML
// aliases of a small file can otherwise expand without end (`x: &a [*a]`) or
// exponentially (an alias bomb).
struct SceneLimits {
    static constexpr std::uintmax_t max_file_bytes = 16u << 20;  // each scene or base file, 16 MiB
    static constexpr int max_depth = 64;                      // lists and maps nested in each other
    static constexpr std::size_t max_values = 250000;         // values of all files, aliases expanded
};

// Load a scene, creating its joints and forces through the registry (only the
// libraries the scene uses are opened). Throws InputError with file:line.
Model load_scene(const std::filesystem::path& file, Registry& registry);
Model load_scene_text(const std::string& yaml, const std::string& label, Registry& registry);

}  // namespace mbd
