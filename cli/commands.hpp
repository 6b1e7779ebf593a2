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

// Each subcommand's registration, one file each (cli/<name>_command.cpp).
using AddCommand = void(CLI::App& app, Commands& commands);
AddCommand add_plugins_command, add_check_command, add_kinematics_command, add_statics_command,
    add_inverse_command, add_simulate_command, add_plugin_check_command, add_bench_command,
    add_stability_command, add_animate_command, add_modes_command, add_sweep_command, add_import_command, add_export_command;

}  // namespace mbd::cli
