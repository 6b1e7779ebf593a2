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
#include <unordered_set>
#include <vector>

namespace mbd::detail {

// The text of a scene file. `named_at` is where the path was written ("file:line" of a
// `base:` key), empty for the scene given on the command line.
std::string read_scene_file(const std::filesystem::path& path, const std::string& named_at = {});

class SceneTreeReader {
public:
    // YAML text (at most SceneLimits::max_file_bytes) -> YAML nodes; syntax errors at file:line.
    // The text must outlive the convert() of the nodes (it finds unclosed quotes in it).
    YAML::Node parse(const std::string& text, const std::string& file);
    // YAML nodes -> Param tree, every node carrying file:line.
    Param convert(const YAML::Node& root, const std::string& file);
    // A top-level `base: FILE` replaced by that file's keys (this file's keys win).
    Param with_base(Param root, const std::string& file, int depth = 0);
    // The `base:` files read so far, in the order they were read.
    const std::vector<std::string>& base_files() const { return base_files_; }

private:
    Param convert(const YAML::Node& node, const std::string& file, int fallback_line);

    // yaml-cpp takes a quoted value that is never closed to run to the end of the text (and
    // the scene's next keys become part of it): refuse it where it opens
    void require_closed_quote(const YAML::Mark& mark, const std::string& file) const;

    const std::string* text_ = nullptr;  // the text parse() read last
    std::vector<YAML::Node> open_;  // the collections being converted, outermost first
    std::size_t values_ = 0;        // values converted so far, all files
    std::size_t repeats_ = 0;       // of those, values an alias repeated (a node met again)
    std::unordered_set<std::size_t> seen_;  // text positions of this file's nodes met so far
    std::vector<std::string> base_files_;
};

}  // namespace mbd::detail
