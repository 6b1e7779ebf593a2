// mbd kinematics SCENE --t-end T --step H [--output out.csv]: kinematically driven
// motion (book Secs. 3.7-3.8), written in the CSV contract of mbd/csv.hpp or
// printed as a short table.
#include "commands.hpp"
#include "options.hpp"

#include <mbd/csv.hpp>
#include <mbd/interrupt.hpp>
#include <mbd/output_file.hpp>
#include <mbd/kinematics.hpp>
#include <mbd/registry.hpp>
#include <mbd/scene.hpp>
#include <mbd/sdk/text.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>

namespace mbd::cli {

namespace {

struct KinematicsArguments {
    std::string scene;
    TimeGrid grid;
    std::string output;
    double tolerance = 1e-10;
    int max_iterations = 50;
    std::string algebra = "auto";
    int rows = 11;
};

void print_table(const std::vector<std::string>& columns, const std::vector<std::vector<double>>& rows) {
    // one block of at most 8 columns (after t) per paragraph, so wide models stay readable
    const size_t per_block = 8;
    for (size_t first = 1; first < columns.size(); first += per_block) {
        const size_t last = std::min(columns.size(), first + per_block);
        if (first > 1) std::cout << '\n';
        std::printf("%12s", "t");
        for (size_t c = first; c < last; ++c) std::printf(" %15s", columns[c].c_str());
        std::printf("\n");
        for (const auto& row : rows) {
            std::printf("%12.6g", row[0]);
            for (size_t c = first; c < last; ++c) std::printf(" %15.8g", row[c]);
            std::printf("\n");
        }
        std::fflush(stdout);
    }
}

}  // namespace

void add_kinematics_command(CLI::App& app, Commands& commands) {
    const auto [args, sub] = scene_subcommand<KinematicsArguments>(
        app, "kinematics",
        "Kinematically driven motion: positions and velocities of every body at t = 0, h, 2h, ..., t_end "
        "(Newton-Raphson assembly at each time)");
    add_time_grid_options(sub, args->grid);
    sub->add_option("-o,--output", args->output,
                    "CSV file (columns: t, positions, velocities per body); without it a short table is printed");
    sub->add_option("--tolerance", args->tolerance, "Newton-Raphson tolerance on max |C|")
        ->capture_default_str()
        ->check(number_between(1e-15, 1.0, "smaller is beneath double-precision round-off"));
    sub->add_option("--max-iterations", args->max_iterations, "Newton-Raphson iterations per output time")
        ->capture_default_str()
        ->check(positive_number());
    sub->add_option("--linear-algebra", args->algebra, "Minimum-norm solver: auto, dense or sparse")
        ->capture_default_str()
        ->check(CLI::IsMember({"auto", "dense", "sparse"}));
    sub->add_option("--rows", args->rows, "Rows of the printed table (without --output)")
        ->capture_default_str()
        ->check(CLI::Range(2, 100000));

    commands[sub] = [args = args] {
        args->grid.intervals();  // the row count, before any work
        KinematicsOptions options;
        options.newton.tolerance = args->tolerance;
        options.newton.max_iterations = args->max_iterations;
        options.newton.algebra = parse_linear_algebra(args->algebra);

        Registry registry;
        const Model model = load_scene_file(args->scene, registry);
        check_output_path(args->output, scene_files(args->scene, model), "--output");
        const std::vector<std::string> columns = motion_columns(model);
        InterruptScope stop_on_signal;  // SIGINT/SIGTERM/SIGHUP end the run after a complete row

        if (!args->output.empty()) {
            CsvWriter writer(args->output, columns);  // the output contract of output_file.hpp
            long samples = 0;
            run_kinematics(
                model, args->grid.t_end, args->grid.step,
                [&](const State& state, const Eigen::VectorXd&) {
                    writer.row(motion_values(model, state));
                    ++samples;
                    return true;
                },
                options);
            writer.close();
            std::cout << "wrote " << samples << " samples (t = 0 to " << args->grid.t_end << ") to " << args->output
                      << '\n';
            return 0;
        }

        // a few evenly spaced samples, always the first and the last
        const long intervals = args->grid.intervals();
        const long stride = std::max(1L, (intervals + args->rows - 2) / (args->rows - 1));
        std::vector<std::vector<double>> rows;
        std::vector<double> last;
        long index = 0;
        run_kinematics(
            model, args->grid.t_end, args->grid.step,
            [&](const State& state, const Eigen::VectorXd&) {
                std::vector<double> values = motion_values(model, state);
                for (double x : values)
                    if (!std::isfinite(x)) throw std::runtime_error("non-finite value in the motion at t = " + format_time(state.t));
                if (index % stride == 0)
                    rows.push_back(values);
                else
                    last = values;
                ++index;
                return true;
            },
            options);
        if (!last.empty() && (rows.empty() || rows.back()[0] < last[0])) {
            if (rows.size() >= static_cast<size_t>(args->rows)) rows.pop_back();
            rows.push_back(last);
        }
        std::cout << "kinematics of " << args->scene << ": " << index << " samples, " << rows.size() << " shown\n\n";
        print_table(columns, rows);
        return 0;
    };
}

}  // namespace mbd::cli
