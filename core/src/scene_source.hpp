// Reading a scene's YAML into a Param tree, within SceneLimits: the file must be a
// regular file of bounded size, and the conversion bounds the nesting depth, refuses
// alias cycles and counts every value an alias repeats. `base:` files go through the
// same reader and share its value budget.
#pragma once

#include <mbd/scene.hpp>
#include <mbd/sdk/params.hpp>

#include <yaml-cpp/yaml.h>

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

namespace mbd::detail {

// The text of a scene file. `named_at` is where the path was written ("file:line" of a
// `base:` key), empty for the scene given on the command line.
std::string read_scene_file(const std::filesystem::path& path, const std::string& named_at = {});

class SceneTreeReader {
public:
    // YAML text (at most SceneLimits::max_file_bytes) -> YAML nodes; syntax errors at file:line.
    YAML::Node parse(const std::string& text, const std::string& file) const;
    // YAML nodes -> Param tree, every node carrying file:line.
    Param convert(const YAML::Node& root, const std::string& file);
    // A top-level `base: FILE` replaced by that file's keys (this file's keys win).
    Param with_base(Param root, const std::string& file, int depth = 0);
    // The `base:` files read so far, in the order they were read.
    const std::vector<std::string>& base_files() const { return base_files_; }

private:
    Param convert(const YAML::Node& node, const std::string& file, int fallback_line);

    std::vector<YAML::Node> open_;  // the collections being converted, outermost first
    std::size_t values_ = 0;        // values converted so far, all files
    std::vector<std::string> base_files_;
};

}  // namespace mbd::detail
