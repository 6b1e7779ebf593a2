// mbd: the command-line front end of the multibody dynamics engine.
//
// Exit codes: 0 success, 1 a failed analysis (assembly, singular configuration,
// I/O), 2 bad input (command line or scene). Every error is printed on stderr as
// "mbd: error: <message>".
#include "commands.hpp"

#include <mbd/kinematics.hpp>
#include <mbd/sdk/formulation.hpp>
#include <mbd/sdk/params.hpp>
#include <mbd/sdk/plugin.hpp>

#include <exception>
#include <iostream>
#include <map>
#include <string>

#ifndef MBD_VERSION
#define MBD_VERSION "unknown"
#endif

int main(int argc, char** argv) {
    CLI::App app{"mbd: multibody dynamics (kinematics, mobility, plugins)", "mbd"};
    app.set_version_flag("--version", std::string("mbd ") + MBD_VERSION + " (plugin ABI " +
                                          std::to_string(MBD_ABI_VERSION) + ")");
    app.require_subcommand(1);

    mbd::cli::Commands actions;
    mbd::cli::add_plugins_command(app, actions);
    mbd::cli::add_check_command(app, actions);
    mbd::cli::add_kinematics_command(app, actions);
    mbd::cli::add_statics_command(app, actions);
    mbd::cli::add_inverse_command(app, actions);
    mbd::cli::add_simulate_command(app, actions);
    mbd::cli::add_plugin_check_command(app, actions);
    mbd::cli::add_bench_command(app, actions);
    mbd::cli::add_stability_command(app, actions);
    mbd::cli::add_animate_command(app, actions);

    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        if (argc > 1 && argv[1][0] != '-' && app.get_subcommands().empty()) {
            std::string known;
            for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; }))
                known += (known.empty() ? "" : ", ") + sub->get_name();
            std::cerr << "mbd: error: unknown command '" << argv[1] << "' (commands: " << known
                      << ")\nRun 'mbd --help' for usage.\n";
            return 2;
        }
        std::cerr << "mbd: error: " << e.what() << "\nRun 'mbd --help' (or 'mbd COMMAND --help') for usage.\n";
        return 2;
    }

    try {
        for (const CLI::App* sub : app.get_subcommands()) {
            auto it = actions.find(sub);
            if (it != actions.end()) return it->second();
        }
        std::cerr << "mbd: error: no command given\n";
        return 2;
    } catch (const mbd::InputError& e) {
        std::cerr << "mbd: error: " << e.what() << '\n';
        return 2;
    } catch (const mbd::DynamicsError& e) {
        std::cerr << "mbd: error: at t = " << e.time() << ": " << e.what() << '\n';
        return 1;
    } catch (const mbd::KinematicsError& e) {
        std::cerr << "mbd: error: " << e.what() << '\n';
        return 1;
    } catch (const std::exception& e) {
        std::cerr << "mbd: error: " << e.what() << '\n';
        return 1;
    } catch (...) {
        std::cerr << "mbd: error: unknown failure\n";
        return 1;
    }
}
