// Scene files (YAML): the format is documented in docs/scene-format.md.
#pragma once

#include <mbd/model.hpp>
#include <mbd/registry.hpp>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

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

// A top-level scene key that belongs to an application, not to the physics (the mbd command's
// `mbd bench` and `mbd stability` keep theirs in the scene file): the loader accepts it beside
// the physics keys and hands its value, unread, to the application (Scene::sections). The core
// names no such key; an application declares its own.
struct SceneSection {
    std::string key;
    std::string reader;  // who reads it, for messages and docs ("mbd bench")
};

// A scene as read: the physics-only Model every analysis runs on, the document as read (every
// `base:` merged in, each node with its file:line, application sections included: what
// `mbd statics --output` rewrites) and the application sections present.
struct Scene {
    Model model;
    std::shared_ptr<const Param> document;
    std::map<std::string, Param> sections;  // by key; only declared keys the scene has
    // The section `key`, or null when the scene has none.
    const Param* section(const std::string& key) const {
        const auto it = sections.find(key);
        return it == sections.end() ? nullptr : &it->second;
    }
};

// The application sections every later load in this process accepts (load_scene and
// read_scene with declared_scene_sections()): an application declares its own once, at its
// start (the mbd command, the Python module). Adds to those declared before; a key declared
// again takes the new reader.
void declare_scene_sections(const std::vector<SceneSection>& sections);
std::vector<SceneSection> declared_scene_sections();

// Read a scene, creating its joints and forces through the registry (only the libraries the
// scene uses are opened), accepting the top-level keys of `sections` beside the physics'. Every
// other unknown key is refused at its file:line with the nearest accepted key. Throws
// InputError with file:line.
Scene read_scene(const std::filesystem::path& file, Registry& registry,
                 const std::vector<SceneSection>& sections = declared_scene_sections());
Scene read_scene_text(const std::string& yaml, const std::string& label, Registry& registry,
                      const std::vector<SceneSection>& sections = declared_scene_sections());

// The Model of read_scene(file, registry) with the declared sections.
Model load_scene(const std::filesystem::path& file, Registry& registry);
Model load_scene_text(const std::string& yaml, const std::string& label, Registry& registry);

}  // namespace mbd
