// The subcommands of the `mbd` command, one file each.
#pragma once

#include <CLI/CLI.hpp>

#include <functional>
#include <map>
#include <string>

namespace mbd::cli {

// A subcommand registers its options on `app` and returns the action to run
// when it is selected. Actions return the process exit code and let exceptions
// propagate to main(), which prints them.
using Action = std::function<int()>;
using Commands = std::map<const CLI::App*, Action>;

// All of the subcommands below, and exactly one of them required (cli/command_line.cpp).
void add_commands(CLI::App& app, Commands& commands);

void add_plugins_command(CLI::App& app, Commands& commands);
void add_check_command(CLI::App& app, Commands& commands);
void add_kinematics_command(CLI::App& app, Commands& commands);
void add_statics_command(CLI::App& app, Commands& commands);
void add_inverse_command(CLI::App& app, Commands& commands);
void add_simulate_command(CLI::App& app, Commands& commands);
void add_plugin_check_command(CLI::App& app, Commands& commands);
void add_bench_command(CLI::App& app, Commands& commands);
void add_stability_command(CLI::App& app, Commands& commands);
void add_animate_command(CLI::App& app, Commands& commands);
void add_modes_command(CLI::App& app, Commands& commands);
void add_sweep_command(CLI::App& app, Commands& commands);

}  // namespace mbd::cli
