// Shared helpers for the test programs: the build tree's plugin registry,
// scene paths, and running the mbd command.
#pragma once

#include <mbd/registry.hpp>
#include <mbd/scene.hpp>

#include <filesystem>
#include <string>

namespace mbd::test {

std::filesystem::path source_dir();
std::filesystem::path build_plugin_dir();
std::filesystem::path scene_path(const std::string& relative);  // under scenes/

// A registry over the build tree's plugins only (MBD_PLUGIN_PATH ignored).
Registry& shared_registry();

struct CommandResult {
    int exit_code = -1;
    std::string out;
    std::string err;
};
// Run the mbd executable with the given argument string (shell-quoted by the caller).
CommandResult run_mbd(const std::string& arguments);
// Run any shell command, capturing stdout and stderr.
CommandResult run_command(const std::string& command);

}  // namespace mbd::test
