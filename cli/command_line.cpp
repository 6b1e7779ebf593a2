// The mbd command line: every subcommand registered on one CLI::App. main.cpp parses and
// runs it; fuzz/command_line_fuzzer.cpp parses with it without running anything.
#include "commands.hpp"

namespace mbd::cli {

void add_commands(CLI::App& app, Commands& commands) {
    app.require_subcommand(1);
    add_plugins_command(app, commands);
    add_check_command(app, commands);
    add_kinematics_command(app, commands);
    add_statics_command(app, commands);
    add_inverse_command(app, commands);
    add_simulate_command(app, commands);
    add_plugin_check_command(app, commands);
    add_bench_command(app, commands);
    add_stability_command(app, commands);
    add_animate_command(app, commands);
    add_modes_command(app, commands);
    add_sweep_command(app, commands);
    add_import_command(app, commands);
    add_export_command(app, commands);
}

}  // namespace mbd::cli
