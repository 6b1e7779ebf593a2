// mbd: the command-line front end of the multibody dynamics engine.
//
// Exit codes (docs/user-guide.md): 0 success; 1 a failed analysis (assembly, a
// singular configuration, a diverging or unstable run, no equilibrium); 2 bad
// input (command line, scene, an output path that is an input or cannot be
// written, a full disk); 128 + N when stopped by signal N (130 SIGINT, 143
// SIGTERM, 129 SIGHUP). Every error is printed on stderr as "mbd: error: ...",
// followed by where the rows of an unfinished output file are (output_file.hpp).
#include "commands.hpp"

#include <mbd/app/scene_sections.hpp>
#include <mbd/interrupt.hpp>
#include <mbd/kinematics.hpp>
#include <mbd/output_file.hpp>
#include <mbd/kit/formulation.hpp>
#include <mbd/sdk/params.hpp>
#include <mbd/sdk/plugin.hpp>
#include <mbd/sdk/text.hpp>

#include <cmath>
#include <cstdio>
#include <exception>
#include <iostream>
#include <map>
#include <string>

#ifndef MBD_VERSION
#define MBD_VERSION "unknown"
#endif

namespace {

// The error, then a line per output file left unfinished; returns `status`.
int report(const std::string& message, int status) {
    std::cerr << "mbd: error: " << message << '\n';
    for (const std::string& note : mbd::take_kept_output_notes()) std::cerr << "mbd: " << note << '\n';
    return status;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"mbd: multibody dynamics. Check a scene (bodies, joints, degrees of freedom), run its kinematics, "
                 "forward dynamics (simulate), statics and inverse dynamics, benchmark it, run the stability "
                 "matrix, and list or check plugins.",
                 "mbd"};
    app.footer(
        "Exit status: 0 success, 1 failed analysis, 2 bad input (command line, scene, output path), 130/143/129 "
        "stopped by SIGINT/SIGTERM/SIGHUP.\nA result file appears under its name only when complete; the rows of "
        "a failed or stopped run stay in NAME.partial. See docs/user-guide.md.");
    app.set_version_flag("--version", std::string("mbd ") + MBD_VERSION + " (plugin ABI " +
                                          std::to_string(MBD_ABI_VERSION) + ", formulation kit ABI " +
                                          std::to_string(MBD_KIT_ABI_VERSION) + ")");

    mbd::declare_application_scene_sections();  // `bench:` and `expect:` (app scene_sections.hpp)
    mbd::cli::Commands actions;
    mbd::cli::add_commands(app, actions);

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
    } catch (const mbd::Interrupted& e) {
        return report("stopped by " + e.signal_name() +
                          (std::isfinite(e.time()) ? " at t = " + mbd::format_time(e.time()) : std::string()) +
                          " before the end of the run",
                      e.exit_status());
    } catch (const mbd::InputError& e) {
        return report(e.what(), 2);
    } catch (const mbd::DynamicsError& e) {
        // a failure without a time (NaN) is not given one
        return report((std::isfinite(e.time()) ? "at t = " + mbd::format_time(e.time()) + ": " : std::string()) + e.what(), 1);
    } catch (const mbd::KinematicsError& e) {
        return report(e.what(), 1);
    } catch (const std::exception& e) {
        return report(e.what(), 1);
    } catch (...) {
        return report("unknown failure", 1);
    }
}
