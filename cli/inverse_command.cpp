// mbd inverse SCENE --t-end T --step H [--output efforts.csv] [--reactions]:
// actuator efforts that produce the motion the drivers prescribe (book Secs.
// 1.7, 4.7, 6.13). See docs/statics.md.
#include "commands.hpp"
#include "options.hpp"

#include <mbd/csv.hpp>
#include <mbd/interrupt.hpp>
#include <mbd/output_file.hpp>
#include <mbd/registry.hpp>
#include <mbd/scene.hpp>
#include <mbd/statics_analysis.hpp>

#include <cstdio>
#include <iostream>
#include <memory>

namespace mbd::cli {

namespace {

struct InverseArguments {
    std::string scene;
    TimeGrid grid;
    std::string output;
    bool reactions = false;
    std::string solver = "ipopt";
};

}  // namespace

void add_inverse_command(CLI::App& app, Commands& commands) {
    const auto [args, sub] = scene_subcommand<InverseArguments>(
        app, "inverse", "Inverse dynamics: actuator efforts for the motion the drivers prescribe, at t = 0, h, ..., t_end",
        "Scene file (YAML) with drivers and 'actuators:'");
    add_time_grid_options(sub, args->grid);
    sub->add_option("-o,--output", args->output, "CSV file: t, one column per actuator (and reactions)");
    sub->add_flag("--reactions", args->reactions, "Add JOINT.fx JOINT.fy JOINT.tz (planar; 6 columns spatial)");
    sub->add_option("--solver", args->solver, "Inverse-dynamics plugin type")->capture_default_str();

    commands[sub] = [args = args] {
        args->grid.intervals();  // the row count, before any work
        Registry registry;
        const Model model = load_scene_file(args->scene, registry);
        check_output_path(args->output, scene_files(args->scene, model), "--output");
        InterruptScope stop_on_signal;  // SIGINT/SIGTERM/SIGHUP end the run after a complete row
        const std::vector<std::string> columns = inverse_columns(model, args->reactions);
        std::unique_ptr<CsvWriter> writer;
        if (!args->output.empty()) writer = std::make_unique<CsvWriter>(args->output, columns);
        long samples = 0;
        if (!writer) {
            for (const auto& c : columns) std::printf("%s%16s", c == "t" ? "" : " ", c.c_str());
            std::printf("\n");
        }
        run_inverse(model, registry, args->grid.t_end, args->grid.step, [&](const InverseSample& s, System& system) {
            const std::vector<double> row = inverse_row(s, system, args->reactions);
            if (writer) {
                writer->row(row);
            } else {
                for (size_t k = 0; k < row.size(); ++k) std::printf("%s%16.9g", k ? " " : "", row[k]);
                std::printf("\n");
            }
            ++samples;
            return true;
        });
        if (writer) {
            writer->close();
            std::cout << "wrote " << samples << " samples of " << model.actuators.size() << " actuator efforts to "
                      << args->output << '\n';
        }
        return 0;
    };
}

}  // namespace mbd::cli
